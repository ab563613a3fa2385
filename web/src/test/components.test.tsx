import { act, fireEvent, render, screen } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { EpisodeControls } from "../components/EpisodeControls";
import { JointStatePanel } from "../components/JointStatePanel";
import { NodeTable } from "../components/NodeTable";
import { layoutTopology, TopologyGraph } from "../components/TopologyGraph";
import { formatValue } from "../format";
import { EventHubProvider } from "../hooks/EventHubContext";
import { EventHub } from "../sse";

function hub(): EventHub {
  return new EventHub("/api/events", () => ({}));
}

function send(target: EventHub, kind: string, data: unknown) {
  act(() => target.dispatch({ kind, data: JSON.stringify(data) }));
}

afterEach(() => vi.unstubAllGlobals());

describe("formatValue", () => {
  it("shows measured values without float noise or trailing zeros", () => {
    expect(formatValue(0.125)).toBe("0.125");
    expect(formatValue(-1.5)).toBe("-1.5");
    expect(formatValue(3)).toBe("3");
    expect(formatValue(0.1 + 0.2)).toBe("0.3");
    expect(formatValue(null)).toBe("—");
  });
});

describe("JointStatePanel", () => {
  it("shows the latest values of the joint-state stream", () => {
    const events = hub();
    const stream = { topic: "/leader/joint_states", message_type: "sensor_msgs/msg/JointState", kind: "joints" as const,
                     stale_after_s: 1.5 };
    render(<EventHubProvider hub={events}><JointStatePanel streams={[stream]} rates={{}} /></EventHubProvider>);
    expect(screen.getByText("waiting for /leader/joint_states")).toBeTruthy();
    send(events, "joints", { topic: "/leader/joint_states", stamp_ns: 1, name: ["gripper"], position: [0.25],
                             velocity: [-1], effort: [null] });
    expect(screen.getByTestId("joint-/leader/joint_states-gripper-position").textContent).toBe("0.25");
    expect(screen.getByTestId("joint-/leader/joint_states-gripper-velocity").textContent).toBe("-1");
    expect(screen.getByTestId("joint-/leader/joint_states-gripper-effort").textContent).toBe("—");
    send(events, "joints", { topic: "/other", stamp_ns: 2, name: ["gripper"], position: [9], velocity: [], effort: [] });
    expect(screen.getByTestId("joint-/leader/joint_states-gripper-position").textContent).toBe("0.25");
  });
});

describe("NodeTable", () => {
  it("posts the action of the button pressed to the node's route", async () => {
    const fetchMock = vi.fn().mockResolvedValue(new Response(JSON.stringify({ node: "leader" }), { status: 200 }));
    vi.stubGlobal("fetch", fetchMock);
    render(<NodeTable nodes={[{ name: "leader", state: "running", pid: 42, restarts: 1, ready: true, since_s: 3 }]} />);
    expect(screen.getByTestId("node-pid-leader").textContent).toBe("42");
    await act(async () => fireEvent.click(screen.getByTestId("node-restart-leader")));
    expect(fetchMock).toHaveBeenCalledWith("/api/nodes/leader/restart", expect.objectContaining({ method: "POST" }));
  });

  it("shows each process's host, and no host column on one computer", () => {
    const { unmount } = render(<NodeTable nodes={[
      { name: "leader", state: "unknown", pid: null, restarts: 0, ready: false, since_s: null, host: "arm" },
      { name: "follower", state: "waiting", pid: 7, restarts: 0, ready: true, since_s: 4, host: "gpu", waiting_for: ["arm"] },
    ]} />);
    expect(screen.getByTestId("node-host-leader").textContent).toBe("arm");
    expect(screen.getByTestId("node-host-follower").textContent).toBe("gpu");
    expect(screen.getByTestId("node-row-leader").textContent).toContain("unknown");
    expect(screen.getByTestId("node-row-follower").querySelector("[title='waiting for arm']")).not.toBeNull();
    expect((screen.getByTestId("node-restart-leader") as HTMLButtonElement).disabled).toBe(true); // no host answers
    unmount();
    render(<NodeTable nodes={[{ name: "leader", state: "running", pid: 42, restarts: 1, ready: true, since_s: 3 }]} />);
    expect(screen.queryByTestId("node-host-leader")).toBeNull();
  });
});

describe("EpisodeControls", () => {
  it("starts an episode with the task text and shows the saved count", async () => {
    const fetchMock = vi.fn().mockResolvedValue(new Response("{}", { status: 200 }));
    vi.stubGlobal("fetch", fetchMock);
    const events = hub();
    render(<EventHubProvider hub={events}><EpisodeControls node="rec" /></EventHubProvider>);
    send(events, "recorder", { node: "rec", known: true, recording: false, event: "saved", message: "saved episode 3", episodes_saved: 4 });
    expect(screen.getByTestId("episodes-saved-rec").textContent).toBe("4 episodes saved");
    fireEvent.change(screen.getByTestId("episode-task-rec"), { target: { value: "stack blocks" } });
    await act(async () => fireEvent.click(screen.getByTestId("episode-start-rec")));
    const [url, init] = fetchMock.mock.calls[0];
    expect(url).toBe("/api/recorders/rec/episode/start");
    expect(JSON.parse(init.body)).toEqual({ task: "stack blocks" });
  });

  it("shows the episode timer and frames, the reset countdown, and sends next and rerecord", async () => {
    const fetchMock = vi.fn().mockResolvedValue(new Response("{}", { status: 200 }));
    vi.stubGlobal("fetch", fetchMock);
    const events = hub();
    render(<EventHubProvider hub={events}><EpisodeControls node="rec" /></EventHubProvider>);
    const progress = { phase: "recording", task: "pick", episodes: 3, elapsed_s: 12.4, remaining_s: 17.6,
                       frames: 372, skipped: 0, writer: "ready", seq: 7 };
    send(events, "recorder", { node: "rec", known: true, recording: true, event: "started", message: "", episodes_saved: 3, progress });
    expect(screen.getByTestId("episode-progress-rec").textContent).toBe("episode 3 · 0:12 / 0:30 · 372 frames");
    send(events, "recorder", { node: "rec", known: true, recording: false, event: "saved", message: "", episodes_saved: 4,
                               progress: { ...progress, phase: "resetting", episodes: 4, elapsed_s: 1, remaining_s: 4.2, frames: 0 } });
    expect(screen.getByTestId("recording-state-rec").textContent).toBe("resetting");
    expect(screen.getByTestId("episode-progress-rec").textContent).toBe("reset · 0:04 left before episode 4");
    await act(async () => fireEvent.click(screen.getByTestId("episode-next-rec")));
    await act(async () => fireEvent.click(screen.getByTestId("episode-rerecord-rec")));
    expect(fetchMock.mock.calls.map(([url]) => url)).toEqual(["/api/recorders/rec/episode/next", "/api/recorders/rec/episode/rerecord"]);
  });
});

describe("TopologyGraph", () => {
  const topology = {
    nodes: [{ name: "leader", type: "MOCK_ENCODER_PUBLISHER", process: "leader" },
            { name: "follower", type: "ACTUATOR_SUBSCRIBER", process: "simulation" }],
    topics: [{ name: "/leader/joint_states", message_type: "sensor_msgs/msg/JointState" }],
    edges: [{ from: "leader", to: "/leader/joint_states" }, { from: "/leader/joint_states", to: "follower" }],
  };

  it("puts publishers, topics and subscribers in successive columns", () => {
    const columns = Object.fromEntries(layoutTopology(topology).map((box) => [box.id, box.column]));
    expect(columns).toEqual({ leader: 0, "/leader/joint_states": 1, follower: 2 });
  });

  it("shows topic rates and the state of each node's process", () => {
    render(<TopologyGraph topology={topology} rates={{ "/leader/joint_states": 29.7 }}
                          nodes={[{ name: "simulation", state: "backoff", pid: null, restarts: 2, ready: false, since_s: 1 }]} />);
    expect(screen.getByTestId("graph-topic-/leader/joint_states").textContent).toContain("30 Hz");
    expect(screen.getByTestId("graph-node-follower").textContent).toContain("backoff");
  });
});
