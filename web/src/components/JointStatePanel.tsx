import * as Tabs from "@radix-ui/react-tabs";
import { useMemo } from "react";
import { useServerTick } from "../hooks/EventHubContext";
import { useJointStates } from "../hooks/streams";
import { staleness } from "../hooks/staleness";
import { formatRate } from "../format";
import type { StreamInfo } from "../types";
import { QUANTITIES } from "../plotScale";
import { JointPlot } from "./JointPlot";
import { JointValuesTable } from "./JointValuesTable";
import { EmptyNote, Panel } from "./Panel";
import { StaleBadge } from "./StaleBadge";

/** Live joint states: one tab per JointState topic, values and position/velocity/effort plots over time. */
export function JointStatePanel({ streams, rates }: { streams: StreamInfo[]; rates: Record<string, number> }) {
  if (streams.length === 0) return null;
  return (
    <Panel title="Joint states">
      <Tabs.Root defaultValue={streams[0].topic}>
        <Tabs.List className="mb-3 flex flex-wrap gap-1 border-b border-slate-800" aria-label="joint state topics">
          {streams.map(({ topic }) => (
            <Tabs.Trigger key={topic} value={topic} data-testid={`joint-tab-${topic}`}
                          className="-mb-px min-w-0 break-all border-b-2 border-transparent px-3 py-1.5 text-left text-xs text-slate-400 data-[state=active]:border-indigo-400 data-[state=active]:text-slate-100">
              {topic} <span className="ml-1 text-slate-500">{formatRate(rates[topic])}</span>
            </Tabs.Trigger>
          ))}
        </Tabs.List>
        {streams.map((stream) => (
          <Tabs.Content key={stream.topic} value={stream.topic}><JointTopic stream={stream} /></Tabs.Content>
        ))}
      </Tabs.Root>
    </Panel>
  );
}

function JointTopic({ stream }: { stream: StreamInfo }) {
  const { topic } = stream;
  const { latest, history } = useJointStates(topic);
  const now = useServerTick();
  // The plots are drawn again at the clock's ticks, not with every refresh of the values: their paths are the
  // page's costliest drawing, and a 10 s window moves by less than 1 % between ticks. The first values at once.
  const plotted = useMemo(() => history, [now, history.length === 0]);
  const age = staleness(latest, stream.stale_after_s, now);
  if (!latest) return <EmptyNote>waiting for {topic}</EmptyNote>;
  return (
    <div className="grid grid-cols-1 items-start gap-4 xl:grid-cols-[minmax(0,1fr)_minmax(0,1.4fr)]">
      {age?.stale && (
        <p className="flex flex-wrap items-center gap-2 text-xs text-amber-200 xl:col-span-2">
          <StaleBadge topic={topic} ageS={age.ageS} />
          no joint state since: the values and plots below are the last ones received
        </p>
      )}
      <div className={`min-w-0 ${age?.stale ? "opacity-50" : ""}`}><JointValuesTable state={latest} /></div>
      <div className="grid min-w-0 grid-cols-1 gap-2">
        {QUANTITIES.map((quantity) => (
          <JointPlot key={quantity} history={plotted} quantity={quantity} now={now} gapS={stream.stale_after_s}
                     stale={age?.stale} />
        ))}
      </div>
    </div>
  );
}
