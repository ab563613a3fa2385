import { useConnected } from "../hooks/EventHubContext";
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

/** The robot's page: topology, processes, live sensors, recording and inference. */
export function App() {
  const { robot, error, unauthorized, retry } = useRobotSummary();
  const status = useNodeStatus();
  const rates = useTopicRates();
  const connected = useConnected();
  if (unauthorized) return <TokenPrompt onToken={retry} />;
  if (error) return <p className="p-8 text-rose-300" role="alert">Cannot load the robot: {error}</p>;
  if (!robot) return <p className="p-8 text-slate-400">Loading…</p>;
  const topicsOf = (kind: string) => robot.streams.filter((s) => s.kind === kind).map((s) => s.topic);
  const nodes = status?.nodes ?? [];
  return (
    <div className="min-h-screen bg-slate-950 text-slate-200">
      <Header robot={robot.robot} status={status} connected={connected} />
      <main className="mx-auto grid max-w-[1600px] gap-4 p-4 lg:grid-cols-2">
        <Panel title="Topology" aside={`${robot.topology.nodes.length} nodes · ${robot.topology.topics.length} topics`}
               className="lg:col-span-2">
          <TopologyGraph topology={robot.topology} rates={rates} nodes={nodes} />
        </Panel>
        <Panel title="Processes" className="lg:col-span-2">
          {nodes.length ? <NodeTable nodes={nodes} /> : <EmptyNote>{status?.error ?? "waiting for the supervisor"}</EmptyNote>}
        </Panel>
        <div className="lg:col-span-2"><JointStatePanel topics={topicsOf("joints")} rates={rates} /></div>
        {topicsOf("image").map((topic) => <CameraView key={topic} topic={topic} rate={rates[topic]} />)}
        {topicsOf("scan").map((topic) => <LidarScanView key={topic} topic={topic} rate={rates[topic]} />)}
        {robot.recorders.map((recorder) => <EpisodeControls key={recorder.node} node={recorder.node} />)}
        {robot.inferences.map((inference) => <InferenceStatus key={inference.node} info={inference} />)}
      </main>
    </div>
  );
}
