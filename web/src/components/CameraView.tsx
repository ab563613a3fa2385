import { useCameraFrame } from "../hooks/streams";
import { formatRate } from "../format";
import { EmptyNote, Panel } from "./Panel";

/** The latest frame of one camera topic. */
export function CameraView({ topic, rate }: { topic: string; rate?: number }) {
  const frame = useCameraFrame(topic);
  return (
    <Panel title={`Camera ${topic}`} aside={frame ? `${frame.width}×${frame.height} · ${formatRate(rate)}` : undefined}>
      {frame ? (
        <img src={`data:image/jpeg;base64,${frame.jpeg}`} alt={`camera ${topic}`} data-stamp-ns={frame.stamp_ns}
             data-testid={`camera-${topic}`} className="mx-auto max-h-96 w-full rounded-lg bg-black object-contain" />
      ) : (
        <EmptyNote>waiting for frames</EmptyNote>
      )}
    </Panel>
  );
}
