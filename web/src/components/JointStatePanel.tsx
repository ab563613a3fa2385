import * as Tabs from "@radix-ui/react-tabs";
import { useJointStates } from "../hooks/streams";
import { formatRate } from "../format";
import { JointPlot } from "./JointPlot";
import { JointValuesTable } from "./JointValuesTable";
import { EmptyNote, Panel } from "./Panel";

/** Live joint states: one tab per JointState topic, values and position/velocity/effort plots. */
export function JointStatePanel({ topics, rates }: { topics: string[]; rates: Record<string, number> }) {
  if (topics.length === 0) return null;
  return (
    <Panel title="Joint states">
      <Tabs.Root defaultValue={topics[0]}>
        <Tabs.List className="mb-3 flex gap-1 border-b border-slate-800" aria-label="joint state topics">
          {topics.map((topic) => (
            <Tabs.Trigger key={topic} value={topic}
                          className="-mb-px border-b-2 border-transparent px-3 py-1.5 text-xs text-slate-400 data-[state=active]:border-indigo-400 data-[state=active]:text-slate-100">
              {topic} <span className="ml-1 text-slate-500">{formatRate(rates[topic])}</span>
            </Tabs.Trigger>
          ))}
        </Tabs.List>
        {topics.map((topic) => (
          <Tabs.Content key={topic} value={topic}><JointTopic topic={topic} /></Tabs.Content>
        ))}
      </Tabs.Root>
    </Panel>
  );
}

function JointTopic({ topic }: { topic: string }) {
  const { latest, history } = useJointStates(topic);
  if (!latest) return <EmptyNote>waiting for {topic}</EmptyNote>;
  return (
    <div className="grid items-start gap-4 xl:grid-cols-[minmax(0,1fr)_minmax(0,1.4fr)]">
      <JointValuesTable state={latest} />
      <div className="grid gap-2">
        {(["position", "velocity", "effort"] as const).map((quantity) => (
          <JointPlot key={quantity} history={history} quantity={quantity} />
        ))}
      </div>
    </div>
  );
}
