import { memo } from "react";
import { formatValue } from "../format";
import { MIN_SPAN, PLOT_WINDOW_S, type Quantity, UNITS, valueRange } from "../plotScale";
import type { JointStateEvent } from "../types";

export const JOINT_COLORS = ["#818cf8", "#34d399", "#fbbf24", "#f472b6", "#38bdf8", "#fb923c", "#a3e635", "#e879f9"];
const TIME_TICKS_S = [PLOT_WINDOW_S, PLOT_WINDOW_S / 2, 0];
const WIDTH = 360;
const HEIGHT = 120;
const MARGIN = 4;

/** One quantity of every joint over the last PLOT_WINDOW_S seconds (time on the server's clock, `now`
 * at the right edge), one line per joint, broken where no message came for `gapS`; greyed out when `stale`.
 * Drawn again only when one of these changes. */
export const JointPlot = memo(function JointPlot({ history, quantity, now, gapS, stale = false }: {
  history: JointStateEvent[]; quantity: Quantity; now: number; gapS: number; stale?: boolean;
}) {
  const shown = history.filter((event) => now - event.server_time_s <= PLOT_WINDOW_S);
  const names = history.at(-1)?.name ?? [];
  const values = shown.flatMap((event) => event[quantity].filter((v): v is number => v !== null));
  const [low, high] = valueRange(values, MIN_SPAN[quantity]);
  const x = (t: number) => WIDTH * (1 - (now - t) / PLOT_WINDOW_S);
  const y = (v: number) => HEIGHT - MARGIN - ((v - low) / (high - low)) * (HEIGHT - 2 * MARGIN);
  const line = (joint: number) => {
    let path = "", previous = -Infinity;
    for (const event of shown) {
      const value = event[quantity][joint];
      if (value == null) continue;
      path += `${event.server_time_s - previous > gapS ? "M" : "L"}${x(event.server_time_s).toFixed(1)},${y(value).toFixed(1)}`;
      previous = event.server_time_s;
    }
    return path;
  };
  const unit = UNITS[quantity];
  return (
    <figure className="rounded-lg bg-slate-950/60 p-2" data-testid={`joint-plot-${quantity}`}
            data-low={low} data-high={high}>
      <figcaption className="mb-1 text-xs text-slate-400">
        <span className="capitalize">{quantity}</span> <span className="text-slate-500">({unit})</span>
        {stale && <span className="ml-1 font-semibold text-amber-300">· stale</span>}
      </figcaption>
      <div className="flex gap-1.5">
        <div className="flex w-12 shrink-0 flex-col justify-between text-right font-mono text-[10px] text-slate-500"
             data-testid={`value-axis-${quantity}`}>
          <span>{formatValue(Number(high.toPrecision(3)))}</span>
          <span>{formatValue(Number(low.toPrecision(3)))}</span>
        </div>
        <svg viewBox={`0 0 ${WIDTH} ${HEIGHT}`} className={`h-28 min-w-0 flex-1 ${stale ? "opacity-40 grayscale" : ""}`}
             preserveAspectRatio="none" role="img" aria-label={`${quantity} of each joint, ${unit}, last ${PLOT_WINDOW_S} s`}>
          <line x1={0} x2={WIDTH} y1={y(0)} y2={y(0)} stroke="#334155" strokeDasharray="3 3" />
          {TIME_TICKS_S.slice(0, -1).map((ago) => (
            <line key={ago} x1={x(now - ago)} x2={x(now - ago)} y1={0} y2={HEIGHT} stroke="#1e293b" />
          ))}
          {names.map((name, joint) => {
            const path = line(joint);
            return path ? <path key={name} d={path} fill="none" strokeWidth={1.5}
                                stroke={JOINT_COLORS[joint % JOINT_COLORS.length]} vectorEffect="non-scaling-stroke" /> : null;
          })}
        </svg>
      </div>
      <div className="ml-[3.375rem] flex justify-between font-mono text-[10px] text-slate-500" data-testid={`time-axis-${quantity}`}>
        {TIME_TICKS_S.map((ago) => <span key={ago}>{ago === 0 ? "now" : `−${ago} s`}</span>)}
      </div>
    </figure>
  );
});
