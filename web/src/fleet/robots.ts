// The fleet's answers (`GET /api/robots`, `GET /api/rollout`), read defensively: the page keeps only entries of the
// documented shape, and makes links of http(s) addresses only, whatever the server or a robot sent.

import type {
  FleetHealth,
  FleetNodeStatus,
  FleetRelease,
  FleetRobot as FleetRobotEntry,
  FleetRolloutEntry as FleetRolloutAnswer,
  FleetRolloutSummary,
} from "../types";

export type { FleetHealth, FleetRelease };
/** What the page shows of a node: its name, state and whether it is ready. */
export type FleetNode = Pick<FleetNodeStatus, "name" | "state" | "ready">;
/** One computer of a robot in the last rollout, as the page keeps it (with a state). */
export type FleetRolloutEntry = FleetRolloutAnswer & { state: string };
/** A robot of the answer as the page keeps it (its `url` an http(s) link or null, its rollout a list). */
export type FleetRobot = Omit<FleetRobotEntry, "nodes" | "rollout"> & {
  nodes: FleetNode[];
  rollout: FleetRolloutEntry[];
};
/** The last rollout's summary as the page keeps it (with a fleet and a state). */
export type FleetRollout = FleetRolloutSummary & { fleet: string; state: string };

export class FleetAnswerError extends Error {}

const LINK_PROTOCOLS = ["http:", "https:"];

/** The address as the browser reads it when it is http(s) with a host, else null. */
export function httpLink(url: unknown): string | null {
  if (typeof url !== "string") return null;
  try {
    const parsed = new URL(url);
    return LINK_PROTOCOLS.includes(parsed.protocol) && parsed.host ? parsed.href : null;
  } catch {
    return null;
  }
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

function text(value: unknown): string | null {
  return typeof value === "string" ? value : null;
}

function readNode(value: unknown): FleetNode | null {
  if (!isRecord(value) || typeof value.name !== "string" || typeof value.state !== "string") return null;
  return { name: value.name, state: value.state, ready: value.ready === true };
}

function readRelease(value: unknown): FleetRelease | null {
  if (!isRecord(value) || typeof value.build !== "string" || !/^[0-9a-f]{1,64}$/.test(value.build)) return null;
  return { build: value.build, built: text(value.built) };
}

function readHealth(value: unknown): FleetHealth | null {
  if (!isRecord(value) || typeof value.ready !== "number" || typeof value.of !== "number") return null;
  return { ready: value.ready, of: value.of };
}

function readRolloutEntry(value: unknown): FleetRolloutEntry | null {
  if (!isRecord(value) || typeof value.name !== "string" || typeof value.state !== "string") return null;
  return {
    name: value.name,
    release: text(value.release),
    state: value.state,
    step: text(value.step),
    message: text(value.message),
    rolled_back_to: text(value.rolled_back_to),
    seconds: typeof value.seconds === "number" ? value.seconds : null,
  };
}

/** One robot of the answer, or null when it is not of the documented shape. */
export function readRobot(value: unknown): FleetRobot | null {
  if (!isRecord(value) || typeof value.name !== "string" || !Array.isArray(value.nodes)) return null;
  if (!(typeof value.last_seen_s === "number" || value.last_seen_s === null) || typeof value.online !== "boolean") {
    return null;
  }
  const nodes = value.nodes.map(readNode);
  if (nodes.some((node) => node === null)) return null;
  const rollout = Array.isArray(value.rollout) ? value.rollout.map(readRolloutEntry) : [];
  return {
    name: value.name,
    nodes: nodes as FleetNode[],
    last_seen_s: value.last_seen_s,
    online: value.online && value.last_seen_s !== null,
    url: httpLink(value.url),
    error: text(value.error),
    release: readRelease(value.release),
    health: readHealth(value.health),
    rollout: rollout.filter((entry): entry is FleetRolloutEntry => entry !== null),
  };
}

/** The robots of an answer, each name once; an answer that is not a list is an error the page shows. */
export function readRobots(answer: unknown): FleetRobot[] {
  if (!Array.isArray(answer)) throw new FleetAnswerError("the fleet answered something other than a list of robots");
  const robots = answer.map(readRobot).filter((robot): robot is FleetRobot => robot !== null);
  return robots.filter((robot, index) => robots.findIndex((other) => other.name === robot.name) === index);
}

/** The last rollout's summary, or null when there is none (or the answer is not of its shape). */
export function readRollout(answer: unknown): FleetRollout | null {
  if (!isRecord(answer) || typeof answer.fleet !== "string" || typeof answer.state !== "string") return null;
  return { fleet: answer.fleet, state: answer.state, started: text(answer.started), finished: text(answer.finished) };
}
