import { formatDuration } from "../format";
import { StateBadge } from "../components/StateBadge";

export interface FleetRobot {
  name: string;
  nodes: { name: string; state: string }[];
  last_seen_s: number;
  url: string | null;
}

const STALE_AFTER_S = 5;

/** Every robot that publishes to the fleet, its processes' states and a link to its own page. */
export function RobotList({ robots }: { robots: FleetRobot[] }) {
  if (robots.length === 0) return <p className="py-10 text-center text-slate-500">No robot has published yet.</p>;
  return (
    <div className="grid gap-4 md:grid-cols-2 xl:grid-cols-3">
      {robots.map((robot) => {
        const running = robot.nodes.filter((n) => n.state === "running").length;
        const stale = robot.last_seen_s > STALE_AFTER_S;
        return (
          <article key={robot.name} data-testid={`robot-${robot.name}`}
                   className="rounded-xl border border-slate-800 bg-slate-900/70 p-4">
            <header className="mb-3 flex items-center justify-between">
              <h2 className="font-semibold text-slate-100">{robot.name}</h2>
              <span className={`text-xs ${stale ? "text-amber-300" : "text-emerald-300"}`}>
                {stale ? `last seen ${formatDuration(robot.last_seen_s)} ago` : "online"}
              </span>
            </header>
            <p className="mb-2 text-sm text-slate-400">{running} / {robot.nodes.length} processes running</p>
            <ul className="mb-3 space-y-1">
              {robot.nodes.map((node) => (
                <li key={node.name} className="flex items-center justify-between text-sm text-slate-300">
                  {node.name} <StateBadge state={node.state} />
                </li>
              ))}
            </ul>
            {robot.url && (
              <a href={robot.url} className="text-sm font-medium text-indigo-300 hover:text-indigo-200">Open dashboard →</a>
            )}
          </article>
        );
      })}
    </div>
  );
}
