// The JSON shapes of the documented routes and events.

export interface TopologyNode { name: string; type: string; process: string }
export interface Topology {
  nodes: TopologyNode[];
  topics: { name: string; message_type: string }[];
  edges: { from: string; to: string }[];
}
/** A topic the page draws; it counts as stale once its newest message is older than `stale_after_s`. */
export interface StreamInfo {
  topic: string;
  message_type: string;
  kind: "joints" | "image" | "scan" | "rate";
  stale_after_s: number;
}
export interface RecorderInfo { node: string; output_directory: string }
export interface InferenceInfo { node: string; model: string; rate_hz: number; inputs: string[]; output: string }
/** A process of the supervisor; a critical one stops the robot when it fails for good. */
export interface ProcessInfo { name: string; type: string; critical: boolean }
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

export type NodeAction = "restart" | "stop" | "start";

export interface NodeStatus {
  name: string;
  state: string;
  pid: number | null;
  /** Restarts the supervisor made by itself (its restart policy); all restarts when
   * `manual_restarts` is absent (a supervisor that does not tell them apart). */
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
export interface HostStatus { name: string; address: string; reachable: boolean; detail: string }
export interface RobotStatus { robot?: string; nodes?: NodeStatus[]; hosts?: HostStatus[]; error?: string; kind?: string }

/** Every event of /api/events carries the server's clock when it was published. */
export interface Stamped { server_time_s: number }
/** The node actions asked through the dashboard and not answered yet. */
export interface ActionsEvent extends Stamped { pending: Record<string, NodeAction> }

export interface JointStateEvent extends Stamped {
  topic: string;
  stamp_ns: number;
  name: string[];
  position: (number | null)[];
  velocity: (number | null)[];
  effort: (number | null)[];
}
export interface ImageEvent extends Stamped { topic: string; stamp_ns: number; width: number; height: number; jpeg: string }
export interface ScanEvent extends Stamped {
  topic: string;
  stamp_ns: number;
  angle_min: number;
  angle_increment: number;
  range_max: number;
  ranges: (number | null)[];
}
/** A recorder's progress report (ai/episode_protocol.py): its phase, the episode or reset timer, frames. */
export interface RecorderProgress {
  phase: "recording" | "resetting" | "idle";
  task: string;
  /** Episodes saved in the dataset: also the index of the episode in progress. */
  episodes: number;
  elapsed_s: number;
  /** Until episode_time_s or the end of the reset period; null when unlimited. */
  remaining_s: number | null;
  frames: number;
  skipped: number;
  writer: "loading" | "ready";
}
export interface RecorderEvent {
  node: string;
  known: boolean;
  recording: boolean;
  event: string;
  message: string;
  episodes_saved: number;
  progress?: RecorderProgress | null;
}
export interface InferenceEvent {
  node: string;
  model: string;
  configured_rate_hz: number;
  rate_hz: number;
  stale_inputs: string[];
}
