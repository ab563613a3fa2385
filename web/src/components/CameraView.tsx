import { useCameraFrame } from "../hooks/streams";
import { useStaleness } from "../hooks/staleness";
import { formatRate } from "../format";
import type { StreamInfo } from "../types";
import { EmptyNote, Panel } from "./Panel";
import { StaleBadge } from "./StaleBadge";

/** The latest frame of one camera topic; dimmed and marked with its age once the stream stopped. */
export function CameraView({ stream, rate }: { stream: StreamInfo; rate?: number }) {
  const { topic } = stream;
  const frame = useCameraFrame(topic);
  const age = useStaleness(frame, stream.stale_after_s);
  return (
    <Panel title={`Camera ${topic}`} aside={frame ? `${frame.width}×${frame.height} · ${formatRate(rate)}` : undefined}>
      {frame ? (
        <div className="relative">
          <img src={`data:image/jpeg;base64,${frame.jpeg}`} alt={`camera ${topic}`} data-stamp-ns={frame.stamp_ns}
               data-testid={`camera-${topic}`} data-stale={age?.stale ? "true" : "false"}
               className={`mx-auto max-h-96 w-full rounded-lg bg-black object-contain ${age?.stale ? "opacity-40 grayscale" : ""}`} />
          {age?.stale && <StaleBadge topic={topic} ageS={age.ageS} className="absolute left-2 top-2" />}
        </div>
      ) : (
        <EmptyNote>waiting for frames</EmptyNote>
      )}
    </Panel>
  );
}
