// One hook per stream of /api/events (and per documented GET route).
import { useCallback, useEffect, useRef, useState } from "react";
import { apiToken, getJson, isUnauthorized } from "../api";
import { PLOT_WINDOW_S } from "../plotScale";
import type {
  ImageEvent, InferenceEvent, JointStateEvent, NodeAction, RecorderEvent, RobotStatus, RobotSummary,
  ScanEvent,
} from "../types";
import { useEventListener, useLatest } from "./EventHubContext";

/** At most this many joint states are kept per topic (PLOT_WINDOW_S at the server's 60 Hz cap, twice over). */
export const HISTORY_LIMIT = 1200;

/** The robot's static summary; `unauthorized` when the robot refused this tab's token, or it has none
 * (then nothing is asked: a request without the token would only be refused). `retry` asks again
 * (after a token was entered). */
export function useRobotSummary(): {
  robot: RobotSummary | null; error: string | null; unauthorized: boolean; retry: () => void;
} {
  const [robot, setRobot] = useState<RobotSummary | null>(null);
  const [error, setError] = useState<{ message: string; unauthorized: boolean } | null>(null);
  const [attempt, setAttempt] = useState(0);
  useEffect(() => {
    if (apiToken() === null) {
      setError({ message: "no access token", unauthorized: true });
      return;
    }
    setError(null);
    getJson<RobotSummary>("/api/robot").then(setRobot,
      (e: Error) => setError({ message: e.message, unauthorized: isUnauthorized(e) }));
  }, [attempt]);
  const retry = useCallback(() => setAttempt((n) => n + 1), []);
  return { robot, error: error?.message ?? null, unauthorized: error?.unauthorized ?? false, retry };
}

export function useNodeStatus(): RobotStatus | null {
  return useLatest("status");
}

/** The node actions asked through the dashboard (by any page) and not answered yet. */
export function usePendingActions(): Record<string, NodeAction> {
  return useLatest("actions")?.pending ?? {};
}

export function useTopicRates(): Record<string, number> {
  return useLatest("rates")?.rates ?? {};
}

export function useCameraFrame(topic: string): ImageEvent | null {
  return useLatest("image", "topic", topic);
}

export function useLaserScan(topic: string): ScanEvent | null {
  return useLatest("scan", "topic", topic);
}

export function useRecorder(node: string): RecorderEvent | null {
  return useLatest("recorder", "node", node);
}

export function useInferenceStatus(node: string): InferenceEvent | null {
  return useLatest("inference", "node", node);
}

/** The page shows joint states at most this often (ms): a robot publishes them at 30-100 Hz, and drawing
 * every one of them kept a core busy with the plots. Every event still enters the history. */
export const JOINT_REFRESH_MS = 100;

type JointStates = { latest: JointStateEvent | null; history: JointStateEvent[] };

/** `history` with `arrived` appended, only the PLOT_WINDOW_S up to the newest (oldest first, at most HISTORY_LIMIT). */
function appendToWindow(history: JointStateEvent[], arrived: JointStateEvent[]): JointStateEvent[] {
  const newest = arrived[arrived.length - 1].server_time_s;
  const since = newest - PLOT_WINDOW_S;
  const inWindow = (event: JointStateEvent) => event.server_time_s >= since && event.server_time_s <= newest;
  return [...history.filter(inWindow), ...arrived.filter(inWindow)].slice(-HISTORY_LIMIT);
}

/** The latest joint state of `topic` and those of the PLOT_WINDOW_S before it (oldest first, at most
 * HISTORY_LIMIT), shown at most every JOINT_REFRESH_MS: an event after a quiet spell at once, those that
 * follow it sooner together at the end of the spell. */
export function useJointStates(topic: string): JointStates {
  const [state, setState] = useState<JointStates>({ latest: null, history: [] });
  const pending = useRef<{ arrived: JointStateEvent[]; lastShownMs: number; timer: number | null }>({
    arrived: [], lastShownMs: -Infinity, timer: null,
  });
  const show = useCallback(() => { // called with at least one event waiting
    const waiting = pending.current;
    const arrived = waiting.arrived;
    waiting.arrived = [];
    waiting.timer = null;
    waiting.lastShownMs = performance.now();
    setState((previous) => ({ latest: arrived[arrived.length - 1], history: appendToWindow(previous.history, arrived) }));
  }, []);
  const listener = useCallback((data: unknown) => {
    const event = data as JointStateEvent;
    if (event.topic !== topic) return;
    const waiting = pending.current;
    waiting.arrived.push(event);
    if (waiting.timer !== null) return;
    const wait = waiting.lastShownMs + JOINT_REFRESH_MS - performance.now();
    if (wait <= 0) show();
    else waiting.timer = window.setTimeout(show, wait);
  }, [topic, show]);
  useEffect(() => () => {
    if (pending.current.timer !== null) window.clearTimeout(pending.current.timer);
  }, []);
  useEventListener("joints", listener);
  return state;
}

/** The last `lines` lines of a node's log, refreshed every `periodMs` while `enabled`; `loads` counts
 * the answers received since it was enabled. */
export function useNodeLog(node: string, enabled: boolean, lines = 200, periodMs = 1000) {
  const [log, setLog] = useState<{ lines: string[]; error: string | null; loads: number }>({
    lines: [], error: null, loads: 0,
  });
  const alive = useRef(true);
  useEffect(() => {
    if (!enabled) return;
    alive.current = true;
    setLog({ lines: [], error: null, loads: 0 });
    const load = () =>
      getJson<{ lines: string[] }>(`/api/nodes/${encodeURIComponent(node)}/logs?lines=${lines}`).then(
        (reply) => alive.current && setLog((previous) => ({ lines: reply.lines, error: null, loads: previous.loads + 1 })),
        (e: Error) => alive.current && setLog((previous) => ({ ...previous, error: e.message })),
      );
    void load();
    const timer = setInterval(load, periodMs);
    return () => { alive.current = false; clearInterval(timer); };
  }, [node, enabled, lines, periodMs]);
  return log;
}
