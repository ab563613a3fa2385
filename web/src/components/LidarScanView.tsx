import { useLaserScan } from "../hooks/streams";
import { useStaleness } from "../hooks/staleness";
import { formatRate } from "../format";
import type { StreamInfo } from "../types";
import { EmptyNote, Panel } from "./Panel";
import { StaleBadge } from "./StaleBadge";

const SIZE = 300;

/** The latest scan of one lidar topic, seen from above (the robot at the centre, forward up); dimmed and
 * marked with its age once the stream stopped. */
export function LidarScanView({ stream, rate }: { stream: StreamInfo; rate?: number }) {
  const { topic } = stream;
  const scan = useLaserScan(topic);
  const age = useStaleness(scan, stream.stale_after_s);
  const points = scan?.ranges.flatMap((range, i) => {
    if (range === null || range <= 0) return [];
    const angle = scan.angle_min + i * scan.angle_increment;
    const r = (range / (scan.range_max || 1)) * (SIZE / 2 - 6);
    return [[SIZE / 2 - r * Math.sin(angle), SIZE / 2 - r * Math.cos(angle)]];
  }) ?? [];
  return (
    <Panel title={`Lidar ${topic}`} aside={scan ? `${points.length} points · ${formatRate(rate)}` : undefined}>
      {scan ? (
        <div className="relative">
          <svg viewBox={`0 0 ${SIZE} ${SIZE}`} className={`mx-auto h-64 w-64 ${age?.stale ? "opacity-40" : ""}`}
               data-testid={`scan-${topic}`} data-points={points.length} role="img"
               aria-label={`lidar ${topic}, range circles every ${formatMeters(scan.range_max / 4)}`}>
            {[0.25, 0.5, 0.75, 1].map((f) => (
              <circle key={f} cx={SIZE / 2} cy={SIZE / 2} r={f * (SIZE / 2 - 6)} fill="none" stroke="#1e293b" />
            ))}
            {points.map(([px, py], i) => <circle key={i} cx={px} cy={py} r={1.6} fill={age?.stale ? "#94a3b8" : "#34d399"} />)}
            <circle cx={SIZE / 2} cy={SIZE / 2} r={4} fill="#818cf8" />
          </svg>
          <p className="text-center text-xs text-slate-500">rings every {formatMeters(scan.range_max / 4)}</p>
          {age?.stale && <StaleBadge topic={topic} ageS={age.ageS} className="absolute left-2 top-2" />}
        </div>
      ) : (
        <EmptyNote>waiting for scans</EmptyNote>
      )}
    </Panel>
  );
}

function formatMeters(meters: number): string {
  return `${Number(meters.toPrecision(2))} m`;
}
