import { formatDuration } from "../format";
import { StateBadge } from "../components/StateBadge";
import type { FleetRobot } from "./robots";

/** Every robot the fleet lists, its processes' states and a link to its own page (http(s) only). */
export function RobotList({ robots }: { robots: FleetRobot[] }) {
  if (robots.length === 0) return <p className="py-10 text-center text-slate-500">No robot has published yet.</p>;
  return (
    <div className="grid gap-4 md:grid-cols-2 xl:grid-cols-3">
      {robots.map((robot) => {
        const running = robot.nodes.filter((n) => n.state === "running").length;
        return (
          <article key={robot.name} data-testid={`robot-${robot.name}`}
                   className="rounded-xl border border-slate-800 bg-slate-900/70 p-4">
            <header className="mb-3 flex items-center justify-between">
              <h2 className="font-semibold text-slate-100">{robot.name}</h2>
              <span className={`text-xs ${robot.online ? "text-emerald-300" : "text-amber-300"}`}>
                {robot.online ? "online" : `offline, last seen ${formatDuration(robot.last_seen_s)} ago`}
              </span>
            </header>
            <p className="mb-2 text-sm text-slate-400">{running} / {robot.nodes.length} processes running</p>
            {robot.error && <p className="mb-2 text-sm text-rose-300">{robot.error}</p>}
            <ul className="mb-3 space-y-1">
              {robot.nodes.map((node, index) => (
                <li key={index} className="flex items-center justify-between text-sm text-slate-300">
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
