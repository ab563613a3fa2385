import { act, fireEvent, render, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { LogDialog } from "../components/LogDialog";
import { NodeTable } from "../components/NodeTable";
import { EventHubProvider } from "../hooks/EventHubContext";
import { EventHub } from "../sse";
import type { NodeStatus, ProcessInfo } from "../types";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

function node(name: string, state: string, extra: Partial<NodeStatus> = {}): NodeStatus {
  return { name, state, pid: state === "running" ? 100 : null, restarts: 0, ready: true, since_s: 1, ...extra };
}

const PROCESSES: ProcessInfo[] = [
  { name: "leader", type: "MOCK_ENCODER_PUBLISHER", critical: true },
  { name: "helper", type: "CUSTOM", critical: false },
  { name: "dashboard", type: "DASHBOARD", critical: false },
];

function answering(status = 200, body: unknown = { node: "x", state: "running", pid: 1 }) {
  const fetchMock = vi.fn().mockImplementation(async () => new Response(JSON.stringify(body), { status }));
  vi.stubGlobal("fetch", fetchMock);
  return fetchMock;
}

function table(nodes: NodeStatus[], connected = true, hub?: EventHub) {
  const element = <NodeTable nodes={nodes} processes={PROCESSES} dashboardProcess="dashboard" connected={connected} />;
  return render(hub ? <EventHubProvider hub={hub}>{element}</EventHubProvider> : element);
}

const button = (action: string, name: string) => screen.getByTestId(`node-${action}-${name}`) as HTMLButtonElement;

describe("LogDialog", () => {
  it("survives refreshes in a browser whose scrollIntoView returns a Promise", async () => {
    // Chromium 156 returns a Promise; an effect that returned it had React call it as its clean-up.
    Object.defineProperty(Element.prototype, "scrollIntoView", {
      configurable: true, value: () => Promise.resolve(),
    });
    let count = 0;
    vi.stubGlobal("fetch", vi.fn(async () => new Response(JSON.stringify({ lines: [`line ${++count}`] }), { status: 200 })));
    const errors: unknown[] = [];
    const onError = (event: ErrorEvent) => errors.push(event.error);
    window.addEventListener("error", onError);
    try {
      render(<LogDialog node="leader" onClose={() => {}} />);
      await waitFor(() => expect(Number(screen.getByTestId("log-lines").dataset.loads)).toBeGreaterThanOrEqual(3),
        { timeout: 5000 });
      expect(screen.getByTestId("log-lines").textContent).toMatch(/^line \d+/);
      expect(errors).toEqual([]);
    } finally {
      window.removeEventListener("error", onError);
      delete (Element.prototype as { scrollIntoView?: unknown }).scrollIntoView;
    }
  }, 10_000);
});

describe("NodeTable", () => {
  it("disables what cannot apply in each state", () => {
    table([node("leader", "running"), node("helper", "stopped"), node("dashboard", "stopping")]);
    expect([button("restart", "leader").disabled, button("stop", "leader").disabled, button("start", "leader").disabled])
      .toEqual([false, false, true]);
    expect([button("restart", "helper").disabled, button("stop", "helper").disabled, button("start", "helper").disabled])
      .toEqual([false, true, false]);
    expect(["restart", "stop", "start"].map((action) => button(action, "dashboard").disabled)).toEqual([true, true, true]);
    expect(button("stop", "helper").title).toBe("helper is stopped");
  });

  it("disables every control while the page is not connected", () => {
    table([node("leader", "running"), node("helper", "stopped")], false);
    for (const name of ["leader", "helper"]) {
      for (const action of ["restart", "stop", "start", "logs"]) expect(button(action, name).disabled).toBe(true);
    }
  });

  it("asks before stopping a critical process, and a no sends nothing", async () => {
    const fetchMock = answering();
    table([node("leader", "running"), node("helper", "running")]);
    fireEvent.click(button("stop", "leader"));
    expect(screen.getByTestId("confirm-dialog").textContent).toContain("critical");
    fireEvent.click(screen.getByTestId("confirm-cancel"));
    expect(screen.queryByTestId("confirm-dialog")).toBeNull();
    expect(fetchMock).not.toHaveBeenCalled();

    fireEvent.click(button("stop", "leader"));
    await act(async () => fireEvent.click(screen.getByTestId("confirm-action")));
    expect(fetchMock).toHaveBeenCalledWith("/api/nodes/leader/stop", expect.objectContaining({ method: "POST" }));
    await act(async () => fireEvent.click(button("restart", "leader"))); // a restart of it does not ask
    await act(async () => fireEvent.click(button("stop", "helper"))); // nor a stop of a process that is not critical
    expect(screen.queryByTestId("confirm-dialog")).toBeNull();
    expect(fetchMock.mock.calls.map(([url]) => url)).toEqual(
      ["/api/nodes/leader/stop", "/api/nodes/leader/restart", "/api/nodes/helper/stop"]);
  });

  it("asks before restarting or stopping the dashboard serving the page, and says what follows", async () => {
    answering(202, { node: "dashboard", state: "stopping", pid: 7 });
    table([node("dashboard", "running")]);
    expect(button("start", "dashboard").disabled).toBe(true);
    fireEvent.click(button("restart", "dashboard"));
    expect(screen.getByTestId("confirm-dialog").textContent).toContain("reconnects by itself");
    await act(async () => fireEvent.click(screen.getByTestId("confirm-action")));
    expect(screen.getByTestId("node-action-message").textContent).toBe("dashboard is restarting: this page reconnects by itself");
    expect(screen.queryByRole("alert")).toBeNull();
  });

  it("shows a restart under way and keeps that process's buttons disabled until it is answered", async () => {
    let answer: (response: Response) => void = () => {};
    vi.stubGlobal("fetch", vi.fn(() => new Promise<Response>((resolve) => { answer = resolve; })));
    table([node("leader", "running"), node("helper", "running")]);
    await act(async () => fireEvent.click(button("restart", "leader")));
    expect(screen.getByTestId("node-pending-leader").textContent).toBe("restarting…");
    expect(["restart", "stop", "start"].map((action) => button(action, "leader").disabled)).toEqual([true, true, true]);
    expect(button("stop", "helper").disabled).toBe(false);
    await act(async () => answer(new Response(JSON.stringify({ node: "leader", state: "running", pid: 5 }), { status: 200 })));
    expect(screen.queryByTestId("node-pending-leader")).toBeNull();
  });

  it("shows the actions other pages asked for, as the dashboard announces them", () => {
    const hub = new EventHub("/api/events", () => ({}));
    table([node("leader", "running")], true, hub);
    act(() => hub.dispatch({ kind: "actions", data: JSON.stringify({ pending: { leader: "stop" }, server_time_s: 1 }) }));
    expect(screen.getByTestId("node-pending-leader").textContent).toBe("stopping…");
    act(() => hub.dispatch({ kind: "actions", data: JSON.stringify({ pending: {}, server_time_s: 2 }) }));
    expect(screen.queryByTestId("node-pending-leader")).toBeNull();
  });

  it("says why the supervisor refused", async () => {
    answering(409, { error: "leader is already running", kind: "conflict" });
    table([node("leader", "backoff")]);
    await act(async () => fireEvent.click(button("start", "leader")));
    expect(screen.getByRole("alert").textContent).toBe("start leader: leader is already running");
  });

  it("counts the restarts asked for apart when the supervisor does", () => {
    table([node("leader", "running", { restarts: 2, manual_restarts: 3 }), node("helper", "running", { restarts: 4 })]);
    expect(screen.getByTestId("node-restarts-leader").textContent).toBe("2 + 3 asked");
    expect(screen.getByTestId("node-restarts-helper").textContent).toBe("4");
    expect(screen.getByTestId("node-critical-leader")).toBeTruthy();
    expect(screen.queryByTestId("node-critical-helper")).toBeNull();
  });
});
