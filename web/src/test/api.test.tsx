import { act, fireEvent, render, screen } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { adoptTokenFromAddress, apiToken } from "../api";
import { App } from "../components/App";
import { EventHubProvider } from "../hooks/EventHubContext";
import { EventHub } from "../sse";

afterEach(() => {
  vi.unstubAllGlobals();
  sessionStorage.clear();
  history.replaceState(null, "", "/");
});

describe("adoptTokenFromAddress", () => {
  it("keeps the printed #token= for this tab and takes it out of the address", () => {
    history.replaceState(null, "", "/?view=1#token=s3cret-token&tab=2");
    adoptTokenFromAddress();
    expect(apiToken()).toBe("s3cret-token");
    expect(window.location.pathname + window.location.search + window.location.hash).toBe("/?view=1#tab=2");
  });

  it("takes a ?token= query the same way, and keeps the token when the address has none", () => {
    history.replaceState(null, "", "/?token=abc-def-ghi");
    adoptTokenFromAddress();
    expect(window.location.search).toBe("");
    history.replaceState(null, "", "/");
    expect(apiToken()).toBe("abc-def-ghi");
  });
});

describe("App without the right token", () => {
  it("asks for the token and loads the robot with it", async () => {
    const robot = { robot: "arm", topology: { nodes: [], topics: [], edges: [] }, streams: [], recorders: [], inferences: [] };
    const fetchMock = vi.fn(async (_url: string, init: RequestInit) => {
      const authorized = (init.headers as Record<string, string>).Authorization === "Bearer typed-token";
      return authorized ? new Response(JSON.stringify(robot), { status: 200 })
        : new Response(JSON.stringify({ error: "missing or wrong bearer token" }), { status: 401 });
    });
    vi.stubGlobal("fetch", fetchMock);
    render(<EventHubProvider hub={new EventHub("/api/events", () => ({}))}><App /></EventHubProvider>);
    await screen.findByTestId("token-prompt");
    fireEvent.change(screen.getByTestId("token-input"), { target: { value: "typed-token" } });
    await act(async () => fireEvent.click(screen.getByTestId("token-submit")));
    expect((await screen.findByTestId("robot-name")).textContent).toBe("arm");
  });
});
