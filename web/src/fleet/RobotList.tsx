import { formatDuration } from "../format";
import { StateBadge } from "../components/StateBadge";
import { RolloutStatus } from "./RolloutStatus";
import type { FleetRobot } from "./robots";

function seen(robot: FleetRobot): string {
  if (robot.last_seen_s === null) return "not heard from";
  return robot.online ? "online" : `offline, last seen ${formatDuration(robot.last_seen_s)} ago`;
}

/** The release a robot runs: its build (the first 12 hex digits of its stamp's hash) and when it was built. */
function ReleaseLine({ robot }: { robot: FleetRobot }) {
  if (!robot.release) return null;
  const built = robot.release.built ? `, built ${robot.release.built.replace("T", " ").slice(0, 19)}` : "";
  return (
    <p className="mb-1 font-mono text-xs text-slate-400" data-testid={`release-${robot.name}`}>
      release {robot.release.build}{built}
    </p>
  );
}

function HealthLine({ robot }: { robot: FleetRobot }) {
  if (!robot.health || robot.health.of === 0) return null;
  const { ready, of } = robot.health;
  return (
    <p className={`mb-2 text-sm ${ready === of ? "text-emerald-300" : "text-amber-300"}`} data-testid={`health-${robot.name}`}>
      ready: {ready} of {of} nodes
    </p>
  );
}

/** The link to a robot's own page, while the robot is online: an offline robot's page does not answer. */
function DashboardLink({ robot }: { robot: FleetRobot }) {
  if (!robot.url) return null;
  if (!robot.online) {
    return (
      <p className="text-sm text-slate-500" data-testid={`dashboard-offline-${robot.name}`}>
        Dashboard not reachable
      </p>
    );
  }
  return <a href={robot.url} className="text-sm font-medium text-indigo-300 hover:text-indigo-200">Open dashboard →</a>;
}

/** Every robot the fleet lists: its release, health, part in the last rollout, processes and, while it is online, a
 * link to its page. */
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
              <span className={`text-xs ${robot.online ? "text-emerald-300" : "text-amber-300"}`}>{seen(robot)}</span>
            </header>
            <ReleaseLine robot={robot} />
            <HealthLine robot={robot} />
            <RolloutStatus robot={robot.name} entries={robot.rollout} />
            {robot.last_seen_s !== null && (
              <p className="mb-2 text-sm text-slate-400">{running} / {robot.nodes.length} processes running</p>
            )}
            {robot.error && <p className="mb-2 text-sm text-rose-300">{robot.error}</p>}
            <ul className="mb-3 space-y-1">
              {robot.nodes.map((node, index) => (
                <li key={index} className="flex items-center justify-between text-sm text-slate-300">
                  {node.name} <StateBadge state={node.state} />
                </li>
              ))}
            </ul>
            <DashboardLink robot={robot} />
          </article>
        );
      })}
    </div>
  );
}
