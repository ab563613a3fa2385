import { formatDuration } from "../format";
import { NODE_ACTIONS, PENDING_LABEL, type ProcessRole, whyNot } from "../nodeActions";
import type { NodeAction, NodeStatus } from "../types";
import { StateBadge } from "./StateBadge";

const CELL = "md:table-cell md:py-2";
const SMALL_LABEL = "mr-1 text-slate-500 md:hidden"; // names a value where the table's header is hidden

/** One process: its host (`showHost`), its state (or the action under way), pid, restarts, uptime, its buttons.
 * A table row on wide screens, a wrapped card on narrow ones. */
export function NodeRow({ node, showHost = false, role, pending, connected, onAction, onLogs }: {
  node: NodeStatus; showHost?: boolean; role: ProcessRole; pending?: NodeAction; connected: boolean;
  onAction: (action: NodeAction) => void; onLogs: () => void;
}) {
  return (
    <tr data-testid={`node-row-${node.name}`}
        className="flex flex-wrap items-center gap-x-4 gap-y-1.5 py-3 text-slate-300 md:table-row md:py-0">
      <td className={`min-w-0 basis-full break-all font-medium text-slate-100 md:basis-auto ${CELL}`}>
        {node.name}
        {node.ready && <span className="ml-2 text-xs text-emerald-400" title="ready" data-testid={`node-ready-${node.name}`}>●</span>}
        {role.critical && (
          <span className="ml-2 rounded bg-slate-800 px-1.5 py-0.5 text-[10px] uppercase tracking-wide text-slate-400"
                data-testid={`node-critical-${node.name}`} title="the robot stops when it fails for good">critical</span>
        )}
        {role.servesThisPage && (
          <span className="ml-2 rounded bg-indigo-500/15 px-1.5 py-0.5 text-[10px] uppercase tracking-wide text-indigo-300"
                title="the dashboard serving this page">this page</span>
        )}
      </td>
      {showHost && (
        <td className={`font-mono text-xs ${CELL}`}>
          <span className={SMALL_LABEL}>host</span><span data-testid={`node-host-${node.name}`}>{node.host}</span>
        </td>
      )}
      <td className={CELL} title={node.waiting_for?.length ? `waiting for ${node.waiting_for.join(", ")}` : undefined}>
        <span className="inline-flex items-center gap-2">
          <StateBadge state={node.state} />
          {pending && (
            <span className="animate-pulse text-xs text-sky-300" data-testid={`node-pending-${node.name}`}>
              {PENDING_LABEL[pending]}
            </span>
          )}
        </span>
      </td>
      <td className={`font-mono text-xs ${CELL}`}>
        <span className={SMALL_LABEL}>pid</span><span data-testid={`node-pid-${node.name}`}>{node.pid ?? "—"}</span>
      </td>
      <td className={CELL} title={restartsTitle(node)}>
        <span className={SMALL_LABEL}>restarts</span>
        <span data-testid={`node-restarts-${node.name}`}>
          {node.restarts}
          {node.manual_restarts !== undefined && <span className="text-slate-500"> + {node.manual_restarts} asked</span>}
        </span>
      </td>
      <td className={`text-slate-400 ${CELL}`}>
        <span className={SMALL_LABEL}>for</span>{formatDuration(node.since_s)}
      </td>
      <td className={`basis-full ${CELL}`}>
        <div className="flex flex-wrap gap-1.5 md:justify-end">
          {NODE_ACTIONS.map((action) => {
            const why = whyNot(action, node.name, node.state, pending, connected, role);
            return (
              <button key={action} type="button" onClick={() => onAction(action)} disabled={why !== null}
                      title={why ?? undefined} data-testid={`node-${action}-${node.name}`}
                      className="rounded-md border border-slate-700 px-2.5 py-1 text-xs capitalize text-slate-200 hover:bg-slate-800 disabled:cursor-not-allowed disabled:opacity-40">
                {action}
              </button>
            );
          })}
          <button type="button" onClick={onLogs} disabled={!connected} data-testid={`node-logs-${node.name}`}
                  className="rounded-md bg-slate-800 px-2.5 py-1 text-xs text-slate-200 hover:bg-slate-700 disabled:opacity-40">
            Logs
          </button>
        </div>
      </td>
    </tr>
  );
}

function restartsTitle(node: NodeStatus): string {
  return node.manual_restarts === undefined
    ? "restarts of any kind (this supervisor does not count those asked for apart)"
    : "restarts after a failure (the restart policy) + restarts asked for (ctl, this page)";
}
