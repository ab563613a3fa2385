import { act, render, screen } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { App } from "../components/App";
import { CameraView } from "../components/CameraView";
import { JointPlot } from "../components/JointPlot";
import { JointStatePanel } from "../components/JointStatePanel";
import { AGE_TICK_MS, EventHubProvider } from "../hooks/EventHubContext";
import { staleness } from "../hooks/staleness";
import { JOINT_REFRESH_MS } from "../hooks/streams";
import { valueRange } from "../plotScale";
import { EventHub } from "../sse";
import type { JointStateEvent, StreamInfo } from "../types";

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
  sessionStorage.clear();
});

const CAMERA: StreamInfo = { topic: "/camera", message_type: "sensor_msgs/msg/Image", kind: "image", stale_after_s: 1.5 };

function send(hub: EventHub, kind: string, data: object) {
  act(() => hub.dispatch({ kind, data: JSON.stringify(data) }));
}

describe("staleness", () => {
  it("measures the age on the server's clock against the stream's threshold", () => {
    expect(staleness(null, 1.5, 100)).toBeNull();
    expect(staleness({ server_time_s: 99 }, 1.5, 100)).toEqual({ ageS: 1, stale: false });
    expect(staleness({ server_time_s: 98 }, 1.5, 100)).toEqual({ ageS: 2, stale: true });
  });
});

describe("CameraView", () => {
  it("marks a frame stale with its age once the stream stopped, on the server's clock", () => {
    const hub = new EventHub("/api/events", () => ({}));
    render(<EventHubProvider hub={hub}><CameraView stream={CAMERA} rate={0} /></EventHubProvider>);
    // The server's clock is an hour ahead of this browser's: ages are measured on the server's.
    const serverNow = Date.now() / 1000 + 3600;
    send(hub, "clock", { server_time_s: serverNow });
    send(hub, "image", { topic: "/camera", stamp_ns: 1, width: 2, height: 2, jpeg: "", server_time_s: serverNow - 4 });
    expect(screen.getByTestId("stale-/camera").textContent).toMatch(/^stale · 4\.\d s$/);
    expect(screen.getByTestId("camera-/camera").dataset.stale).toBe("true");
    send(hub, "image", { topic: "/camera", stamp_ns: 2, width: 2, height: 2, jpeg: "", server_time_s: serverNow });
    expect(screen.queryByTestId("stale-/camera")).toBeNull();
    expect(screen.getByTestId("camera-/camera").dataset.stale).toBe("false");
  });
});

function joints(t: number, position: number): JointStateEvent {
  return { topic: "/j", stamp_ns: 0, name: ["a"], position: [position], velocity: [0], effort: [0], server_time_s: t };
}

describe("JointPlot", () => {
  it("keeps noise far below its smallest span flat instead of blowing it up to full height", () => {
    expect(valueRange([1e-12, -1e-12], 0.1)).toEqual([-0.05, 0.05]);
    expect(valueRange([0.5, 2], 0.1)).toEqual([0, 2]);
    const history = Array.from({ length: 50 }, (_, i) => joints(100 + i * 0.1, i % 2 ? 1e-12 : -1e-12));
    const { container } = render(<JointPlot history={history} quantity="position" now={105} gapS={1.5} />);
    const ys = [...container.querySelector("path")!.getAttribute("d")!.matchAll(/[ML][\d.]+,([\d.]+)/g)].map((m) => Number(m[1]));
    expect(ys).toHaveLength(50);
    expect(Math.max(...ys) - Math.min(...ys)).toBeLessThan(0.5); // of a 120-unit high plot
  });

  it("has units, a time axis up to now, and breaks its lines where messages stopped", () => {
    const history = [joints(95, 0.1), joints(96, 0.2), joints(100, 0.3), joints(100.5, 0.4)];
    const { container } = render(<JointPlot history={history} quantity="velocity" now={101} gapS={1.5} stale />);
    expect(screen.getByTestId("joint-plot-velocity").querySelector("figcaption")!.textContent).toBe("velocity (rad/s)· stale");
    expect(screen.getByTestId("time-axis-velocity").textContent).toBe("−10 s−5 snow");
    const path = container.querySelector("path")!.getAttribute("d")!;
    expect(path.match(/M/g)).toHaveLength(2); // 96 -> 100 is a gap of 4 s
    const xs = [...path.matchAll(/[ML]([\d.]+),/g)].map((m) => Number(m[1]));
    expect(xs).toEqual([144, 180, 324, 342]); // 360 wide for 10 s: now - 6 s, now - 5 s, now - 1 s, now - 0.5 s
  });
});

describe("JointStatePanel", () => {
  it("shows a burst of joint states once per refresh, the first at once, and plots every one at the clock's tick", () => {
    vi.useFakeTimers({ toFake: ["setTimeout", "clearTimeout", "setInterval", "clearInterval", "performance", "Date"] });
    const hub = new EventHub("/api/events", () => ({}));
    const stream: StreamInfo = { topic: "/j", message_type: "sensor_msgs/msg/JointState", kind: "joints", stale_after_s: 1.5 };
    const { container } = render(<EventHubProvider hub={hub}><JointStatePanel streams={[stream]} rates={{}} /></EventHubProvider>);
    const start = Date.now() / 1000;
    for (let i = 0; i < 20; i++) send(hub, "joints", joints(start + i * 0.001, i + 1));
    const position = () => screen.getByTestId("joint-/j-a-position").textContent;
    const plotted = () => container.querySelector("[data-testid=joint-plot-position] path")!.getAttribute("d")!;
    expect(position()).toBe("1"); // the first of the burst at once; the other 19 wait for the refresh
    expect(plotted().match(/[ML]/g)).toHaveLength(1);
    act(() => vi.advanceTimersByTime(JOINT_REFRESH_MS));
    expect(position()).toBe("20");
    expect(plotted().match(/[ML]/g)).toHaveLength(1); // the plots wait for the clock's next tick
    act(() => vi.advanceTimersByTime(AGE_TICK_MS - JOINT_REFRESH_MS));
    expect(plotted().match(/[ML]/g)).toHaveLength(20);
  });
});

describe("App", () => {
  it("asks a tab without a token for it and sends nothing the robot would refuse", () => {
    const fetchMock = vi.fn();
    vi.stubGlobal("fetch", fetchMock);
    const hub = new EventHub("/api/events", () => ({}));
    const start = vi.spyOn(hub, "start");
    render(<EventHubProvider hub={hub}><App /></EventHubProvider>);
    expect(screen.getByTestId("token-prompt")).toBeTruthy();
    expect(fetchMock).not.toHaveBeenCalled();
    expect(start).not.toHaveBeenCalled();
  });
});
