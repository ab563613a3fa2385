import { formatAge } from "../format";
import { useConnected, useEventStream, useServerNow } from "../hooks/EventHubContext";
import { useNodeStatus, useRobotSummary, useTopicRates } from "../hooks/streams";
import { CameraView } from "./CameraView";
import { EpisodeControls } from "./EpisodeControls";
import { Header } from "./Header";
import { InferenceStatus } from "./InferenceStatus";
import { JointStatePanel } from "./JointStatePanel";
import { LidarScanView } from "./LidarScanView";
import { NodeTable } from "./NodeTable";
import { EmptyNote, Panel } from "./Panel";
import { TokenPrompt } from "./TokenPrompt";
import { TopologyGraph } from "./TopologyGraph";
import type { RobotStatus, Stamped, StreamKind } from "../types";

/** The robot's page: topology, processes, live sensors, recording and inference. */
export function App() {
  const { robot, error, unauthorized, retry } = useRobotSummary();
  useEventStream(robot !== null);
  const status = useNodeStatus();
  const rates = useTopicRates();
  const connected = useConnected();
  if (unauthorized) return <TokenPrompt onToken={retry} />;
  if (error) return <p className="p-8 text-rose-300" role="alert">Cannot load the robot: {error}</p>;
  if (!robot) return <p className="p-8 text-slate-400">Loading…</p>;
  const streamsOf = (kind: StreamKind) => robot.streams.filter((s) => s.kind === kind);
  const nodes = status?.nodes ?? [];
  return (
    <div className="min-h-screen bg-slate-950 text-slate-200">
      <Header robot={robot.robot} status={status} connected={connected} />
      <main className="mx-auto grid max-w-[1600px] gap-4 p-2 sm:p-4 lg:grid-cols-2">
        <Panel title="Topology" aside={`${robot.topology.nodes.length} nodes · ${robot.topology.topics.length} topics`}
               className="lg:col-span-2">
          <TopologyGraph topology={robot.topology} rates={rates} nodes={nodes} />
        </Panel>
        <Panel title="Processes" className="lg:col-span-2"
               aside={!connected && status ? <StatusAge status={status} /> : undefined}>
          {nodes.length ? (
            <div className={connected ? "" : "opacity-60"}>
              <NodeTable nodes={nodes} processes={robot.processes} dashboardProcess={robot.dashboard_process}
                         connected={connected} />
            </div>
          ) : <EmptyNote>{status?.error ?? "waiting for the supervisor"}</EmptyNote>}
        </Panel>
        <div className="min-w-0 lg:col-span-2"><JointStatePanel streams={streamsOf("joints")} rates={rates} /></div>
        {streamsOf("image").map((stream) => <CameraView key={stream.topic} stream={stream} rate={rates[stream.topic]} />)}
        {streamsOf("scan").map((stream) => <LidarScanView key={stream.topic} stream={stream} rate={rates[stream.topic]} />)}
        {robot.recorders.map((recorder) => <EpisodeControls key={recorder.node} node={recorder.node} />)}
        {robot.inferences.map((inference) => <InferenceStatus key={inference.node} info={inference} />)}
      </main>
    </div>
  );
}

/** How old the process states shown are, while the page is not connected. */
function StatusAge({ status }: { status: RobotStatus & Partial<Stamped> }) {
  const now = useServerNow();
  if (status.server_time_s === undefined) return null;
  return (
    <span className="font-semibold text-amber-300" data-testid="status-age">
      not live: as of {formatAge(Math.max(0, now - status.server_time_s))} ago
    </span>
  );
}
