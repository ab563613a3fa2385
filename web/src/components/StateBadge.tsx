const COLORS: Record<string, string> = {
  running: "bg-emerald-500/15 text-emerald-300 ring-emerald-500/40",
  starting: "bg-sky-500/15 text-sky-300 ring-sky-500/40",
  pending: "bg-slate-500/15 text-slate-300 ring-slate-500/40",
  backoff: "bg-amber-500/15 text-amber-300 ring-amber-500/40",
  stopping: "bg-amber-500/15 text-amber-300 ring-amber-500/40",
  stopped: "bg-slate-500/15 text-slate-300 ring-slate-500/40",
  finished: "bg-slate-500/15 text-slate-300 ring-slate-500/40",
  failed: "bg-rose-500/15 text-rose-300 ring-rose-500/40",
  waiting: "bg-amber-500/15 text-amber-300 ring-amber-500/40",
  unknown: "bg-slate-500/15 text-slate-400 ring-slate-500/40",
};

/** A node's supervisor state as a coloured pill. */
export function StateBadge({ state }: { state: string }) {
  const color = COLORS[state] ?? COLORS.pending;
  return (
    <span data-testid="state"
          className={`inline-flex items-center rounded-full px-2 py-0.5 text-xs font-medium ring-1 ring-inset ${color}`}>
      {state}
    </span>
  );
}

export const STATE_STROKE: Record<string, string> = {
  running: "#34d399", starting: "#38bdf8", backoff: "#fbbf24", stopping: "#fbbf24", failed: "#fb7185",
};
