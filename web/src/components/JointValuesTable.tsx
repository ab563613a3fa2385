import { formatValue } from "../format";
import type { JointStateEvent } from "../types";
import { JOINT_COLORS } from "./JointPlot";

/** The latest position, velocity and effort of each joint, as numbers. */
export function JointValuesTable({ state }: { state: JointStateEvent }) {
  return (
    <table className="w-full text-sm" data-stamp-ns={state.stamp_ns} data-testid={`joint-values-${state.topic}`}>
      <thead className="text-xs uppercase tracking-wider text-slate-500">
        <tr><th className="pb-1 text-left font-medium">Joint</th><th className="pb-1 text-right font-medium">Position</th>
          <th className="pb-1 text-right font-medium">Velocity</th><th className="pb-1 text-right font-medium">Effort</th></tr>
      </thead>
      <tbody className="font-mono text-xs text-slate-200">
        {state.name.map((name, joint) => (
          <tr key={name}>
            <td className="py-0.5 font-sans text-slate-300">
              <span className="mr-2 inline-block h-2 w-2 rounded-full" style={{ background: JOINT_COLORS[joint % JOINT_COLORS.length] }} />
              {name}
            </td>
            {(["position", "velocity", "effort"] as const).map((quantity) => (
              <td key={quantity} className="py-0.5 text-right" data-testid={`joint-${state.topic}-${name}-${quantity}`}>
                {formatValue(state[quantity][joint])}
              </td>
            ))}
          </tr>
        ))}
      </tbody>
    </table>
  );
}
