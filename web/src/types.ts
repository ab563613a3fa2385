// The JSON shapes of the dashboard's and the fleet view's API, rendered from runtime/joshua_runtime/dashboard/api.schema.json
// by `make api-types` (runtime/joshua_runtime/dashboard/api_typescript.py): do not edit.

/** The version of the API these types describe (MAJOR.MINOR, see the schema's description). */
export const API_VERSION = "1.0";

/** How the page shows a topic: joint states, camera frames, lidar scans, or only its message rate. */
export type StreamKind = "joints" | "image" | "scan" | "rate";

export type NodeAction = "restart" | "stop" | "start";

/** A recorder's episode commands (ai/episode_protocol.py's COMMANDS). */
export type EpisodeAction = "start" | "stop" | "discard" | "next" | "rerecord";

/** What went wrong: a refusal the supervisor names, or a failure to get its answer at all (control_client.py). */
export type ErrorKind = "conflict" | "not_found" | "stopping" | "bad_request" | "forbidden" | "busy" | "invalid_build" | "preflight" | "refused" | "unreachable" | "timeout" | "broken";

/** A refused or failed request; `kind` when the supervisor's refusal or failure says what went wrong. */
export interface ErrorReply {
  error: string;
  kind?: ErrorKind;
}

export interface TopologyNode {
  name: string;
  type: string;
  process: string;
}

export interface TopologyTopic {
  name: string;
  message_type: string;
}

export interface TopologyEdge {
  from: string;
  to: string;
}

export interface Topology {
  nodes: TopologyNode[];
  topics: TopologyTopic[];
  edges: TopologyEdge[];
}

/** A topic the page draws; it counts as stale once its newest message is older than `stale_after_s`. */
export interface StreamInfo {
  topic: string;
  message_type: string;
  kind: StreamKind;
  stale_after_s: number;
}

export interface RecorderInfo {
  node: string;
  output_directory: string;
}

export interface InferenceInfo {
  node: string;
  model: string;
  rate_hz: number;
  inputs: string[];
  output: string;
}

/** A process of the supervisor; a critical one stops the robot when it fails for good. */
export interface ProcessInfo {
  name: string;
  type: string;
  critical: boolean;
}

/** GET /api/robot: everything static about the robot, read from its build. */
export interface RobotSummary {
  robot: string;
  topology: Topology;
  streams: StreamInfo[];
  processes: ProcessInfo[];
  /** The process serving this page (null when it is served otherwise). */
  dashboard_process: string | null;
  recorders: RecorderInfo[];
  inferences: InferenceInfo[];
}

/** A process as the supervisor reports it (`ctl status --json`). */
export interface NodeStatus {
  name: string;
  state: string;
  pid: number | null;
  /** Restarts the supervisor made by itself (its restart policy); all restarts when `manual_restarts` is absent (a supervisor that does not tell them apart). */
  restarts: number;
  /** Restarts asked for (ctl, this page), when the supervisor counts them apart. */
  manual_restarts?: number;
  ready: boolean;
  /** Seconds in this state; null for a process of a host never heard from. */
  since_s: number | null;
  /** The computer that runs it, on a robot on several hosts. */
  host?: string;
  /** The unreachable hosts that alone publish what it reads (its state is then `waiting`). */
  waiting_for?: string[];
}

/** A host of a robot on several, as its dashboard's host hears it. */
export interface HostStatus {
  name: string;
  address: string;
  reachable: boolean;
  detail: string;
}

/** GET /api/status: the supervisor's status as it answers it (its other keys pass through), or why there is none. */
export interface RobotStatus {
  robot?: string;
  nodes?: NodeStatus[];
  hosts?: HostStatus[];
  error?: string;
  kind?: ErrorKind;
}

export interface LogsReply {
  lines: string[];
}

/** The supervisor's answer to a node action (202: this dashboard's own process, stopping as asked, or a node still stopping or starting when the supervisor's answer did not come in time). */
export interface NodeActionReply {
  node: string;
  state: string;
  pid: number | null;
}

/** The episode command sent to a recorder node: `start TASK`, `stop` or `discard`. */
export interface EpisodeReply {
  node: string;
  command: string;
}

/** Every event of /api/events carries the server's clock (Unix time, s) when it was published. */
export interface Stamped {
  server_time_s: number;
}

export type StatusEvent = Stamped & RobotStatus;

/** The node actions asked through the dashboard and not answered yet. */
export interface ActionsEvent extends Stamped {
  pending: Record<string, NodeAction>;
}

/** Messages a second of each topic of the robot, over the last report period. */
export interface RatesEvent extends Stamped {
  rates: Record<string, number>;
}

export interface JointStateEvent extends Stamped {
  topic: string;
  stamp_ns: number;
  name: string[];
  position: (number | null)[];
  velocity: (number | null)[];
  effort: (number | null)[];
}

/** A camera frame as a base64 JPEG. */
export interface ImageEvent extends Stamped {
  topic: string;
  stamp_ns: number;
  width: number;
  height: number;
  jpeg: string;
}

export interface ScanEvent extends Stamped {
  topic: string;
  stamp_ns: number;
  angle_min: number;
  angle_increment: number;
  range_max: number;
  ranges: (number | null)[];
}

export type RecorderPhase = "recording" | "resetting" | "idle";

/** A recorder's progress report (ai/episode_protocol.py): its phase, the episode or reset timer, frames. */
export interface RecorderProgress {
  phase: RecorderPhase;
  task: string;
  /** Episodes saved in the dataset: also the index of the episode in progress. */
  episodes: number;
  elapsed_s: number;
  /** Until episode_time_s or the end of the reset period; null when unlimited. */
  remaining_s: number | null;
  frames: number;
  skipped: number;
  writer: "loading" | "ready";
  /** The seq of the recorder's last episode event when this report was made. */
  seq: number;
}

/** A recorder's last episode event, and its last progress report (null before the first). */
export interface RecorderEvent extends Stamped {
  node: string;
  known: boolean;
  recording: boolean;
  event: string;
  message: string;
  episodes_saved: number;
  progress: RecorderProgress | null;
}

export interface InferenceEvent extends Stamped {
  node: string;
  model: string;
  configured_rate_hz: number;
  rate_hz: number;
  stale_inputs: string[];
}

/** A node of a robot as the fleet view keeps it (fleet_status.py's schema). */
export interface FleetNodeStatus {
  name: string;
  state: string;
  pid: number | null;
  restarts: number;
  ready: boolean;
  since_s: number | null;
}

/** The build a robot runs: its hash's first 12 hex digits and when it was written (ISO 8601). */
export interface FleetRelease {
  build: string;
  built: string | null;
}

/** How many of a robot's nodes are ready, of all. */
export interface FleetHealth {
  ready: number;
  of: number;
}

/** One computer of a robot in the last rollout (`arm_1`, or `split.arm`), from joshua-fleet deploy's state file. */
export interface FleetRolloutEntry {
  name: string;
  release: string | null;
  state: string | null;
  step: string | null;
  message: string | null;
  rolled_back_to: string | null;
  seconds: number | null;
}

/** One robot the fleet view heard from, or a robot of the last rollout that publishes nothing (`last_seen_s` null); `url`: the robot's own page (http or https). */
export interface FleetRobot {
  name: string;
  last_seen_s: number | null;
  online: boolean;
  nodes: FleetNodeStatus[];
  url: string | null;
  error: string | null;
  release: FleetRelease | null;
  health: FleetHealth | null;
  rollout: FleetRolloutEntry[] | null;
}

/** The last rollout of joshua-fleet deploy: its fleet, its state and when it started and finished (ISO 8601). */
export interface FleetRolloutSummary {
  fleet: string | null;
  state: string | null;
  started: string | null;
  finished: string | null;
}

/** GET /api/rollout: the last rollout's summary, null when there is none. */
export type FleetRollout = FleetRolloutSummary | null;

/** GET /api/robots: every robot heard from, sorted by name. */
export type FleetRobots = FleetRobot[];

/** The data of each event of /api/events, by its name. */
export interface ServerEvents {
  clock: Stamped;
  status: StatusEvent;
  actions: ActionsEvent;
  rates: RatesEvent;
  joints: JointStateEvent;
  image: ImageEvent;
  scan: ScanEvent;
  recorder: RecorderEvent;
  inference: InferenceEvent;
}
