import { useState } from "react";
import { postJson } from "../api";
import { useRecorder } from "../hooks/streams";
import type { RecorderProgress } from "../types";
import { Panel } from "./Panel";

type EpisodeAction = "start" | "stop" | "discard" | "next" | "rerecord";

/** Minutes and seconds of a timer: "0:07", "12:30". */
export function formatTimer(seconds: number): string {
  const whole = Math.max(0, Math.floor(seconds));
  return `${Math.floor(whole / 60)}:${String(whole % 60).padStart(2, "0")}`;
}

/** What the recorder is doing, in words: "episode 3 · 0:12 / 0:30 · 368 frames", "reset · 0:04 left". */
export function describeProgress(progress: RecorderProgress): string {
  const { phase, episodes, elapsed_s, remaining_s, frames } = progress;
  if (phase === "recording") {
    const length = remaining_s === null ? formatTimer(elapsed_s) : `${formatTimer(elapsed_s)} / ${formatTimer(elapsed_s + remaining_s)}`;
    return `episode ${episodes} · ${length} · ${frames} frames`;
  }
  if (phase === "resetting") return `reset · ${formatTimer(remaining_s ?? 0)} left before episode ${episodes}`;
  return "idle";
}

/** A recorder's episodes: start with a task text, stop (save), next, re-record, discard; its timer and frames. */
export function EpisodeControls({ node }: { node: string }) {
  const recorder = useRecorder(node);
  const [task, setTask] = useState("");
  const [error, setError] = useState<string | null>(null);

  async function send(action: EpisodeAction) {
    setError(null);
    try {
      await postJson(`/api/recorders/${encodeURIComponent(node)}/episode/${action}`, action === "start" ? { task } : undefined);
    } catch (e) {
      setError((e as Error).message);
    }
  }

  const progress = recorder?.progress ?? null;
  const recording = recorder?.recording ?? false;
  const resetting = progress?.phase === "resetting";
  const state = recorder === null || !recorder.known ? "waiting for the recorder" : recording ? "recording" : resetting ? "resetting" : "idle";
  return (
    <Panel title={`Recording · ${node}`} aside={
      <span data-testid={`episodes-saved-${node}`}>{recorder?.episodes_saved ?? 0} episodes saved</span>
    }>
      <div className="mb-3 flex items-center gap-2 text-sm">
        <span className={`h-2.5 w-2.5 rounded-full ${recording ? "animate-pulse bg-rose-500" : resetting ? "bg-amber-400" : "bg-slate-600"}`} />
        <span className="text-slate-200" data-testid={`recording-state-${node}`}>{state}</span>
        {progress && (
          <span className="ml-auto font-mono text-xs text-slate-300" data-testid={`episode-progress-${node}`}>
            {describeProgress(progress)}{progress.writer === "loading" ? " · writer loading" : ""}
          </span>
        )}
      </div>
      {recorder?.message && (
        <p className="mb-3 truncate text-xs text-slate-400" data-testid={`recorder-message-${node}`}>{recorder.message}</p>
      )}
      <div className="flex flex-wrap gap-2">
        <input value={task} onChange={(e) => setTask(e.target.value)} placeholder="Task, e.g. pick the red cube"
               aria-label="task" data-testid={`episode-task-${node}`}
               className="min-w-48 flex-1 rounded-md border border-slate-700 bg-slate-950 px-3 py-1.5 text-sm text-slate-100 placeholder:text-slate-600 focus:border-indigo-500 focus:outline-none" />
        <button type="button" onClick={() => send("start")} disabled={recording} data-testid={`episode-start-${node}`}
                className="rounded-md bg-rose-600 px-3 py-1.5 text-sm font-medium text-white hover:bg-rose-500 disabled:opacity-40">
          Start
        </button>
        <button type="button" onClick={() => send("stop")} disabled={!recording && !resetting} data-testid={`episode-stop-${node}`}
                className="rounded-md bg-slate-700 px-3 py-1.5 text-sm text-slate-100 hover:bg-slate-600 disabled:opacity-40">
          Stop &amp; save
        </button>
        <button type="button" onClick={() => send("next")} data-testid={`episode-next-${node}`}
                title="Save this episode and record the next one (after the reset period); during a reset, start it now"
                className="rounded-md bg-slate-700 px-3 py-1.5 text-sm text-slate-100 hover:bg-slate-600 disabled:opacity-40">
          Next →
        </button>
        <button type="button" onClick={() => send("rerecord")} data-testid={`episode-rerecord-${node}`}
                title="Drop this episode (or remove the one just saved) and record it again"
                className="rounded-md border border-slate-700 px-3 py-1.5 text-sm text-slate-300 hover:bg-slate-800 disabled:opacity-40">
          ← Re-record
        </button>
        <button type="button" onClick={() => send("discard")} disabled={!recording} data-testid={`episode-discard-${node}`}
                className="rounded-md border border-slate-700 px-3 py-1.5 text-sm text-slate-300 hover:bg-slate-800 disabled:opacity-40">
          Discard
        </button>
      </div>
      {error && <p className="mt-2 text-sm text-rose-300" role="alert">{error}</p>}
    </Panel>
  );
}
