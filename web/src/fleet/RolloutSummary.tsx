import type { FleetRobot, FleetRollout } from "./robots";

/** The last rollout in one line: its fleet, state, and how many computers have their new release. */
export function RolloutSummary({ rollout, robots }: { rollout: FleetRollout | null; robots: FleetRobot[] }) {
  if (!rollout) return null;
  const entries = robots.flatMap((robot) => robot.rollout);
  const updated = entries.filter((entry) => entry.state === "updated").length;
  const when = rollout.finished ? `, finished ${rollout.finished.replace("T", " ").slice(0, 19)}` :
    rollout.started ? `, started ${rollout.started.replace("T", " ").slice(0, 19)}` : "";
  return (
    <p className="text-xs text-slate-300" data-testid="rollout-summary">
      rollout of {rollout.fleet}: {rollout.state}{when}; {updated} of {entries.length} on their new release
    </p>
  );
}
