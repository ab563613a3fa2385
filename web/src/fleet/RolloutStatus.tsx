import type { FleetRolloutEntry } from "./robots";

const COLORS: Record<string, string> = {
  updated: "text-emerald-300",
  deploying: "text-sky-300",
  waiting: "text-slate-400",
  not_started: "text-slate-400",
  rolled_back: "text-amber-300",
  failed: "text-rose-300",
};

/** What the last rollout did to one computer of a robot, in one line. */
function describe(entry: FleetRolloutEntry): string {
  const release = entry.release ? ` ${entry.release}` : "";
  switch (entry.state) {
    case "updated":
      return `release${release} rolled out` + (entry.seconds !== null ? ` in ${entry.seconds.toFixed(1)} s` : "");
    case "deploying":
      return `rolling out release${release}`;
    case "waiting":
      return `waiting for release${release}`;
    case "not_started":
      return "not started: " + (entry.message ?? "the rollout stopped");
    case "rolled_back":
      return "rolled back: " + (entry.message ?? "");
    case "failed": {
      const back = entry.rolled_back_to ? `; back on ${entry.rolled_back_to}` : "";
      return `failed at ${entry.step ?? "?"}: ${entry.message ?? ""}${back}`;
    }
    default:
      return entry.state;
  }
}

/** The robot's part of the last rollout: one line per computer (hosts of a robot on several are named). */
export function RolloutStatus({ robot, entries }: { robot: string; entries: FleetRolloutEntry[] }) {
  if (entries.length === 0) return null;
  return (
    <ul className="mb-2 space-y-1" data-testid={`rollout-${robot}`}>
      {entries.map((entry) => (
        <li key={entry.name} className={`text-xs ${COLORS[entry.state] ?? "text-slate-300"}`}>
          {entry.name !== robot && <span className="text-slate-400">{entry.name.slice(robot.length + 1)}: </span>}
          {describe(entry)}
        </li>
      ))}
    </ul>
  );
}
