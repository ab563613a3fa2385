import type { JointStateEvent } from "../types";

export const JOINT_COLORS = ["#818cf8", "#34d399", "#fbbf24", "#f472b6", "#38bdf8", "#fb923c", "#a3e635", "#e879f9"];
const WIDTH = 360;
const HEIGHT = 120;

type Quantity = "position" | "velocity" | "effort";

/** One quantity of every joint over the recent joint states, one line per joint. */
export function JointPlot({ history, quantity }: { history: JointStateEvent[]; quantity: Quantity }) {
  const names = history.at(-1)?.name ?? [];
  const values = history.flatMap((event) => event[quantity].filter((v): v is number => v !== null));
  const low = Math.min(0, ...values), high = Math.max(0, ...values);
  const span = high - low || 1;
  const x = (i: number) => (i / Math.max(1, history.length - 1)) * WIDTH;
  const y = (v: number) => HEIGHT - 4 - ((v - low) / span) * (HEIGHT - 8);
  return (
    <figure className="rounded-lg bg-slate-950/60 p-2" data-testid={`joint-plot-${quantity}`}>
      <figcaption className="mb-1 flex justify-between text-xs text-slate-400">
        <span className="capitalize">{quantity}</span>
        <span className="font-mono">{values.length ? `${low.toFixed(2)} … ${high.toFixed(2)}` : "no data"}</span>
      </figcaption>
      <svg viewBox={`0 0 ${WIDTH} ${HEIGHT}`} className="h-28 w-full" preserveAspectRatio="none">
        <line x1={0} x2={WIDTH} y1={y(0)} y2={y(0)} stroke="#334155" strokeDasharray="3 3" />
        {names.map((name, joint) => {
          const points = history
            .map((event, i) => (event[quantity][joint] == null ? null : `${x(i).toFixed(1)},${y(event[quantity][joint]!).toFixed(1)}`))
            .filter(Boolean)
            .join(" ");
          return points ? <polyline key={name} points={points} fill="none" strokeWidth={1.5}
                                    stroke={JOINT_COLORS[joint % JOINT_COLORS.length]} vectorEffect="non-scaling-stroke" /> : null;
        })}
      </svg>
    </figure>
  );
}
