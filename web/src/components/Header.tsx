import type { RobotStatus } from "../types";

/** The robot's name, whether the live stream is connected, how many nodes run and, on a robot on several
 * hosts, which hosts are heard from. */
export function Header({ robot, status, connected }: { robot: string; status: RobotStatus | null; connected: boolean }) {
  const nodes = status?.nodes ?? [];
  const running = nodes.filter((node) => node.state === "running").length;
  return (
    <header className="flex flex-wrap items-center justify-between gap-3 border-b border-slate-800 bg-slate-900/80 px-4 py-3 sm:px-6">
      <div className="flex items-center gap-3">
        <div className="grid h-8 w-8 place-items-center rounded-lg bg-indigo-500/20 font-bold text-indigo-300">J</div>
        <div>
          <h1 className="text-lg font-semibold text-slate-100" data-testid="robot-name">{robot}</h1>
          <p className="text-xs text-slate-400">Robot dashboard</p>
        </div>
      </div>
      <div className="flex min-w-0 flex-wrap items-center gap-x-4 gap-y-1 text-sm">
        {status?.error ? (
          <span className="break-words text-rose-300" data-testid="status-error">supervisor: {status.error}</span>
        ) : (
          <span className="text-slate-300">{running} / {nodes.length} processes running</span>
        )}
        {status?.hosts?.map((host) => (
          <span key={host.name} data-testid={`host-${host.name}`} title={host.reachable ? host.address : host.detail}
                className={`rounded-full px-2 py-0.5 font-mono text-xs ring-1 ring-inset ${
                  host.reachable ? "text-emerald-300 ring-emerald-500/40" : "text-rose-300 ring-rose-500/40"}`}>
            {host.name}{host.reachable ? "" : " unreachable"}
          </span>
        ))}
        <span className="flex items-center gap-1.5 text-slate-400" data-testid="connection">
          <span className={`h-2 w-2 rounded-full ${connected ? "bg-emerald-400" : "bg-rose-500"}`} />
          {connected ? "live" : "reconnecting"}
        </span>
      </div>
    </header>
  );
}
