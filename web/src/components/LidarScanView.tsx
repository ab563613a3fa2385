import { useLaserScan } from "../hooks/streams";
import { formatRate } from "../format";
import { EmptyNote, Panel } from "./Panel";

const SIZE = 300;

/** The latest scan of one lidar topic, seen from above (the robot at the centre, forward up). */
export function LidarScanView({ topic, rate }: { topic: string; rate?: number }) {
  const scan = useLaserScan(topic);
  const points = scan?.ranges.flatMap((range, i) => {
    if (range === null || range <= 0) return [];
    const angle = scan.angle_min + i * scan.angle_increment;
    const r = (range / (scan.range_max || 1)) * (SIZE / 2 - 6);
    return [[SIZE / 2 - r * Math.sin(angle), SIZE / 2 - r * Math.cos(angle)]];
  }) ?? [];
  return (
    <Panel title={`Lidar ${topic}`} aside={scan ? `${points.length} points · ${formatRate(rate)}` : undefined}>
      {scan ? (
        <svg viewBox={`0 0 ${SIZE} ${SIZE}`} className="mx-auto h-64 w-64" data-testid={`scan-${topic}`}
             data-points={points.length}>
          {[0.25, 0.5, 0.75, 1].map((f) => (
            <circle key={f} cx={SIZE / 2} cy={SIZE / 2} r={f * (SIZE / 2 - 6)} fill="none" stroke="#1e293b" />
          ))}
          {points.map(([px, py], i) => <circle key={i} cx={px} cy={py} r={1.6} fill="#34d399" />)}
          <circle cx={SIZE / 2} cy={SIZE / 2} r={4} fill="#818cf8" />
        </svg>
      ) : (
        <EmptyNote>waiting for scans</EmptyNote>
      )}
    </Panel>
  );
}
