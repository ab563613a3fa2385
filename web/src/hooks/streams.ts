// One hook per stream of /api/events (and per documented GET route).
import { useCallback, useEffect, useRef, useState } from "react";
import { getJson, isUnauthorized } from "../api";
import type {
  ImageEvent, InferenceEvent, JointStateEvent, RecorderEvent, RobotStatus, RobotSummary, ScanEvent,
} from "../types";
import { useEventListener, useLatest } from "./EventHubContext";

export const HISTORY_LENGTH = 150;

/** The robot's static summary; `unauthorized` when the robot refused this tab's token (or it has none).
 * `retry` asks again (after a token was entered). */
export function useRobotSummary(): {
  robot: RobotSummary | null; error: string | null; unauthorized: boolean; retry: () => void;
} {
  const [robot, setRobot] = useState<RobotSummary | null>(null);
  const [error, setError] = useState<{ message: string; unauthorized: boolean } | null>(null);
  const [attempt, setAttempt] = useState(0);
  useEffect(() => {
    setError(null);
    getJson<RobotSummary>("/api/robot").then(setRobot,
      (e: Error) => setError({ message: e.message, unauthorized: isUnauthorized(e) }));
  }, [attempt]);
  const retry = useCallback(() => setAttempt((n) => n + 1), []);
  return { robot, error: error?.message ?? null, unauthorized: error?.unauthorized ?? false, retry };
}

export function useNodeStatus(): RobotStatus | null {
  return useLatest<RobotStatus>("status");
}

export function useTopicRates(): Record<string, number> {
  return useLatest<{ rates: Record<string, number> }>("rates")?.rates ?? {};
}

export function useCameraFrame(topic: string): ImageEvent | null {
  return useLatest<ImageEvent>("image", "topic", topic);
}

export function useLaserScan(topic: string): ScanEvent | null {
  return useLatest<ScanEvent>("scan", "topic", topic);
}

export function useRecorder(node: string): RecorderEvent | null {
  return useLatest<RecorderEvent>("recorder", "node", node);
}

export function useInferenceStatus(node: string): InferenceEvent | null {
  return useLatest<InferenceEvent>("inference", "node", node);
}

/** The latest joint state of `topic` and the recent ones (oldest first, at most HISTORY_LENGTH). */
export function useJointStates(topic: string): { latest: JointStateEvent | null; history: JointStateEvent[] } {
  const [state, setState] = useState<{ latest: JointStateEvent | null; history: JointStateEvent[] }>({
    latest: null, history: [],
  });
  const listener = useCallback((data: unknown) => {
    const event = data as JointStateEvent;
    if (event.topic !== topic) return;
    setState((previous) => ({ latest: event, history: [...previous.history, event].slice(-HISTORY_LENGTH) }));
  }, [topic]);
  useEventListener("joints", listener);
  return state;
}

/** The last `lines` lines of a node's log, refreshed every `periodMs` while `enabled`. */
export function useNodeLog(node: string, enabled: boolean, lines = 200, periodMs = 1000) {
  const [log, setLog] = useState<{ lines: string[]; error: string | null }>({ lines: [], error: null });
  const alive = useRef(true);
  useEffect(() => {
    if (!enabled) return;
    alive.current = true;
    const load = () =>
      getJson<{ lines: string[] }>(`/api/nodes/${encodeURIComponent(node)}/logs?lines=${lines}`).then(
        (reply) => alive.current && setLog({ lines: reply.lines, error: null }),
        (e: Error) => alive.current && setLog((previous) => ({ ...previous, error: e.message })),
      );
    void load();
    const timer = setInterval(load, periodMs);
    return () => { alive.current = false; clearInterval(timer); };
  }, [node, enabled, lines, periodMs]);
  return log;
}
