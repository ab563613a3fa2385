import { formatAge } from "../format";

/** Says that a stream stopped, and how long ago its newest message arrived. */
export function StaleBadge({ topic, ageS, className = "" }: { topic: string; ageS: number; className?: string }) {
  return (
    <span role="status" data-testid={`stale-${topic}`} title={`no message on ${topic} for ${formatAge(ageS)}`}
          className={`inline-flex items-center gap-1 rounded-md bg-amber-500/90 px-2 py-0.5 text-xs font-semibold text-slate-950 shadow ${className}`}>
      stale · {formatAge(ageS)}
    </span>
  );
}
