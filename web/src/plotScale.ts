// The scales of the joint-state plots: time window, units and the value axis.

export const QUANTITIES = ["position", "velocity", "effort"] as const;
export type Quantity = (typeof QUANTITIES)[number];
/** sensor_msgs/JointState's units (REP 103) for revolute joints; a prismatic joint's are m, m/s and N. */
export const UNITS: Record<Quantity, string> = { position: "rad", velocity: "rad/s", effort: "N·m" };
/** The smallest span a plot's value axis shows, in its unit: noise far below it stays a flat line
 * instead of being blown up to the plot's height. */
export const MIN_SPAN: Record<Quantity, number> = { position: 0.1, velocity: 0.1, effort: 0.1 };
/** The plots show the last PLOT_WINDOW_S seconds, up to the server's clock now. */
export const PLOT_WINDOW_S = 10;

/** The value axis: from the lowest to the highest value (0 always in view), at least `minSpan` wide. */
export function valueRange(values: number[], minSpan: number): [number, number] {
  const low = Math.min(0, ...values), high = Math.max(0, ...values);
  if (high - low >= minSpan) return [low, high];
  const middle = (low + high) / 2;
  return [middle - minSpan / 2, middle + minSpan / 2];
}
