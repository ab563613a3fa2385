// The fleet's answer (`GET /api/robots`), read defensively: the page keeps only entries of the documented
// shape, and makes links of http(s) addresses only, whatever the server or a robot sent.

import type { FleetNodeStatus, FleetRobot as FleetRobotEntry } from "../types";

/** What the page shows of a node: its name and state. */
export type FleetNode = Pick<FleetNodeStatus, "name" | "state">;
/** A robot of the answer as the page keeps it (its `url` an http(s) link or null). */
export type FleetRobot = Omit<FleetRobotEntry, "nodes"> & { nodes: FleetNode[] };

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

function readNode(value: unknown): FleetNode | null {
  if (!isRecord(value) || typeof value.name !== "string" || typeof value.state !== "string") return null;
  return { name: value.name, state: value.state };
}

/** One robot of the answer, or null when it is not of the documented shape. */
export function readRobot(value: unknown): FleetRobot | null {
  if (!isRecord(value) || typeof value.name !== "string" || !Array.isArray(value.nodes)) return null;
  if (typeof value.last_seen_s !== "number" || typeof value.online !== "boolean") return null;
  const nodes = value.nodes.map(readNode);
  if (nodes.some((node) => node === null)) return null;
  return {
    name: value.name,
    nodes: nodes as FleetNode[],
    last_seen_s: value.last_seen_s,
    online: value.online,
    url: httpLink(value.url),
    error: typeof value.error === "string" ? value.error : null,
  };
}

/** The robots of an answer, each name once; an answer that is not a list is an error the page shows. */
export function readRobots(answer: unknown): FleetRobot[] {
  if (!Array.isArray(answer)) throw new FleetAnswerError("the fleet answered something other than a list of robots");
  const robots = answer.map(readRobot).filter((robot): robot is FleetRobot => robot !== null);
  return robots.filter((robot, index) => robots.findIndex((other) => other.name === robot.name) === index);
}
