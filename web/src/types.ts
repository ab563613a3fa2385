// The JSON shapes of the documented routes and events.

export interface TopologyNode { name: string; type: string; process: string }
export interface Topology {
  nodes: TopologyNode[];
  topics: { name: string; message_type: string }[];
  edges: { from: string; to: string }[];
}
export interface StreamInfo { topic: string; message_type: string; kind: "joints" | "image" | "scan" | "rate" }
export interface RecorderInfo { node: string; output_directory: string }
export interface InferenceInfo { node: string; model: string; rate_hz: number; inputs: string[]; output: string }
export interface RobotSummary {
  robot: string;
  topology: Topology;
  streams: StreamInfo[];
  recorders: RecorderInfo[];
  inferences: InferenceInfo[];
}

export interface NodeStatus {
  name: string;
  state: string;
  pid: number | null;
  restarts: number;
  ready: boolean;
  since_s: number;
}
export interface RobotStatus { robot?: string; nodes?: NodeStatus[]; error?: string }

export interface JointStateEvent {
  topic: string;
  stamp_ns: number;
  name: string[];
  position: (number | null)[];
  velocity: (number | null)[];
  effort: (number | null)[];
}
export interface ImageEvent { topic: string; stamp_ns: number; width: number; height: number; jpeg: string }
export interface ScanEvent {
  topic: string;
  stamp_ns: number;
  angle_min: number;
  angle_increment: number;
  range_max: number;
  ranges: (number | null)[];
}
export interface RecorderEvent {
  node: string;
  known: boolean;
  recording: boolean;
  event: string;
  message: string;
  episodes_saved: number;
}
export interface InferenceEvent {
  node: string;
  model: string;
  configured_rate_hz: number;
  rate_hz: number;
  stale_inputs: string[];
}
