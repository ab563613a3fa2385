import { useState } from "react";
import { postJson } from "../api";
import { formatDuration } from "../format";
import type { NodeStatus } from "../types";
import { LogDialog } from "./LogDialog";
import { StateBadge } from "./StateBadge";

const ACTIONS = ["restart", "stop", "start"] as const;

/** The supervisor's processes with restart / stop / start buttons and a log tail each. */
export function NodeTable({ nodes }: { nodes: NodeStatus[] }) {
  const [busy, setBusy] = useState<string | null>(null);
  const [error, setError] = useState<string | null>(null);
  const [logNode, setLogNode] = useState<string | null>(null);

  async function act(node: string, action: (typeof ACTIONS)[number]) {
    setBusy(`${node}:${action}`);
    setError(null);
    try {
      await postJson(`/api/nodes/${encodeURIComponent(node)}/${action}`);
    } catch (e) {
      setError(`${action} ${node}: ${(e as Error).message}`);
    } finally {
      setBusy(null);
    }
  }

  return (
    <div>
      <table className="w-full text-left text-sm">
        <thead className="text-xs uppercase tracking-wider text-slate-500">
          <tr>
            <th className="pb-2 font-medium">Process</th><th className="pb-2 font-medium">State</th>
            <th className="pb-2 font-medium">PID</th><th className="pb-2 font-medium">Restarts</th>
            <th className="pb-2 font-medium">Since</th><th className="pb-2 text-right font-medium">Actions</th>
          </tr>
        </thead>
        <tbody className="divide-y divide-slate-800">
          {nodes.map((node) => (
            <tr key={node.name} data-testid={`node-row-${node.name}`} className="text-slate-300">
              <td className="py-2 font-medium text-slate-100">
                {node.name}
                {node.ready && <span className="ml-2 text-xs text-emerald-400" title="ready">●</span>}
              </td>
              <td className="py-2"><StateBadge state={node.state} /></td>
              <td className="py-2 font-mono text-xs" data-testid={`node-pid-${node.name}`}>{node.pid ?? "—"}</td>
              <td className="py-2">{node.restarts}</td>
              <td className="py-2 text-slate-400">{formatDuration(node.since_s)}</td>
              <td className="py-2">
                <div className="flex justify-end gap-1.5">
                  {ACTIONS.map((action) => (
                    <button key={action} type="button" onClick={() => act(node.name, action)}
                            disabled={busy !== null} data-testid={`node-${action}-${node.name}`}
                            className="rounded-md border border-slate-700 px-2 py-1 text-xs capitalize text-slate-200 hover:bg-slate-800 disabled:opacity-40">
                      {action}
                    </button>
                  ))}
                  <button type="button" onClick={() => setLogNode(node.name)} data-testid={`node-logs-${node.name}`}
                          className="rounded-md bg-slate-800 px-2 py-1 text-xs text-slate-200 hover:bg-slate-700">
                    Logs
                  </button>
                </div>
              </td>
            </tr>
          ))}
        </tbody>
      </table>
      {error && <p className="mt-3 text-sm text-rose-300" role="alert">{error}</p>}
      <LogDialog node={logNode} onClose={() => setLogNode(null)} />
    </div>
  );
}
