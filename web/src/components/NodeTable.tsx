import { useState } from "react";
import { ApiError, postJson } from "../api";
import { usePendingActions } from "../hooks/streams";
import { type Confirmation, confirmation, type ProcessRole } from "../nodeActions";
import type { NodeAction, NodeStatus, ProcessInfo } from "../types";
import { ConfirmDialog } from "./ConfirmDialog";
import { LogDialog } from "./LogDialog";
import { NodeRow } from "./NodeRow";

const HEAD = "pb-2 font-medium";

/** The supervisor's processes with restart / stop / start buttons and a log tail each; on a robot on several
 * hosts, each process's host. Buttons that cannot apply are disabled; stopping a critical process or the
 * dashboard itself asks first; an action under way (from any page) shows until the supervisor answers. */
export function NodeTable({ nodes, processes = [], dashboardProcess = null, connected = true }: {
  nodes: NodeStatus[]; processes?: ProcessInfo[]; dashboardProcess?: string | null; connected?: boolean;
}) {
  const announced = usePendingActions();
  const [asked, setAsked] = useState<Record<string, NodeAction>>({});
  const [question, setQuestion] = useState<{ node: string; action: NodeAction; confirmation: Confirmation } | null>(null);
  const [message, setMessage] = useState<{ text: string; error: boolean } | null>(null);
  const [logNode, setLogNode] = useState<string | null>(null);
  const onHosts = nodes.some((node) => node.host !== undefined);
  const critical = new Map(processes.map((process) => [process.name, process.critical]));
  const roleOf = (name: string): ProcessRole => ({
    critical: critical.get(name) ?? false, servesThisPage: name === dashboardProcess,
  });
  // What a lost connection announced may have ended since: only this page's own requests count then.
  const pendingOf = (name: string) => asked[name] ?? (connected ? announced[name] : undefined);

  function press(node: string, action: NodeAction) {
    const question = confirmation(action, node, roleOf(node));
    if (question) setQuestion({ node, action, confirmation: question });
    else void act(node, action);
  }

  async function act(node: string, action: NodeAction) {
    setAsked((previous) => ({ ...previous, [node]: action }));
    setMessage(null);
    const leaving = node === dashboardProcess && action !== "start";
    const farewell = action === "restart" ? `${node} is restarting: this page reconnects by itself`
      : `${node} is stopping: this page is offline until it is started again`;
    try {
      await postJson(`/api/nodes/${encodeURIComponent(node)}/${action}`);
      if (leaving) setMessage({ text: farewell, error: false });
    } catch (e) {
      // The dashboard serving this page may end before its answer is out: its connection goes with it.
      const lost = leaving && !(e instanceof ApiError);
      setMessage(lost ? { text: farewell, error: false } : { text: `${action} ${node}: ${(e as Error).message}`, error: true });
    } finally {
      setAsked(({ [node]: _done, ...others }) => others);
    }
  }

  return (
    <div>
      <table className="block w-full text-left text-sm md:table">
        <thead className="hidden text-xs uppercase tracking-wider text-slate-500 md:table-header-group">
          <tr>
            <th className={HEAD}>Process</th>{onHosts && <th className={HEAD}>Host</th>}
            <th className={HEAD}>State</th><th className={HEAD}>PID</th>
            <th className={HEAD}>Restarts</th><th className={HEAD}>Since</th><th className={`${HEAD} text-right`}>Actions</th>
          </tr>
        </thead>
        <tbody className="block divide-y divide-slate-800 md:table-row-group">
          {nodes.map((node) => (
            <NodeRow key={node.name} node={node} showHost={onHosts} role={roleOf(node.name)} pending={pendingOf(node.name)}
                     connected={connected} onAction={(action) => press(node.name, action)}
                     onLogs={() => setLogNode(node.name)} />
          ))}
        </tbody>
      </table>
      {message && (
        <p className={`mt-3 text-sm ${message.error ? "text-rose-300" : "text-sky-300"}`}
           role={message.error ? "alert" : "status"} data-testid="node-action-message">{message.text}</p>
      )}
      <ConfirmDialog question={question?.confirmation ?? null} onAnswer={(yes) => {
        if (yes && question) void act(question.node, question.action);
        setQuestion(null);
      }} />
      <LogDialog node={logNode} onClose={() => setLogNode(null)} />
    </div>
  );
}
