// Which process actions apply in which supervisor state, and which ask first.
import type { NodeAction } from "./types";

export const NODE_ACTIONS: readonly NodeAction[] = ["restart", "stop", "start"];

/** The supervisor states (see its `status --json`) in which an action cannot apply: the supervisor
 * would refuse it, or it would do nothing; `unknown` is a process of a host not heard from (none answers). */
const INAPPLICABLE: Record<NodeAction, readonly string[]> = {
  start: ["running", "stopping", "pending", "unknown"],
  stop: ["stopped", "finished", "failed", "stopping", "unknown"],
  restart: ["stopping", "unknown"],
};

export const PENDING_LABEL: Record<NodeAction, string> = {
  restart: "restarting…", stop: "stopping…", start: "starting…",
};

/** What the page knows of a process besides its state. */
export interface ProcessRole {
  critical: boolean;
  /** It is the dashboard serving this page. */
  servesThisPage: boolean;
}

/** Why `action` cannot apply to a process in `state` now, or null when it can. */
export function whyNot(action: NodeAction, name: string, state: string, pending: NodeAction | undefined,
                       connected: boolean, role: ProcessRole): string | null {
  if (!connected) return "the page has lost its connection to the dashboard";
  if (pending) return `${name} is ${PENDING_LABEL[pending]}`;
  if (INAPPLICABLE[action].includes(state)) return `${name} is ${state}`;
  if (action === "start" && role.servesThisPage) return `${name} serves this page: it is running`;
  return null;
}

export interface Confirmation { title: string; detail: string; action: string }

/** What to ask before `action` on a process, or null when it goes ahead at once: stopping or
 * restarting the dashboard that serves this page, and stopping a critical process. */
export function confirmation(action: NodeAction, name: string, role: ProcessRole): Confirmation | null {
  if (role.servesThisPage && action === "restart") {
    return {
      title: `Restart ${name}, the dashboard serving this page?`,
      detail: "This page loses its connection while it restarts and reconnects by itself.",
      action: `Restart ${name}`,
    };
  }
  if (role.servesThisPage && action === "stop") {
    return {
      title: `Stop ${name}, the dashboard serving this page?`,
      detail: `This page loses its connection and its controls until ${name} is started again on the robot ` +
        `(python3 OUT/supervisor.py ctl start ${name}).`,
      action: `Stop ${name}`,
    };
  }
  if (role.critical && action === "stop") {
    return {
      title: `Stop ${name}? It is a critical process`,
      detail: `The robot may not work without ${name}. It stays stopped, whatever its restart policy, until started again.`,
      action: `Stop ${name}`,
    };
  }
  return null;
}
