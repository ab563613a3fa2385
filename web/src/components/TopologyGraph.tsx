import { formatRate } from "../format";
import type { NodeStatus, Topology } from "../types";
import { STATE_STROKE } from "./StateBadge";

const COLUMN_WIDTH = 210;
const ROW_HEIGHT = 58;
const BOX_WIDTH = 170;
const BOX_HEIGHT = 40;
// Below this width the graph's labels would be too small to read: its frame scrolls sideways instead.
const MIN_READABLE_WIDTH = 560;

export interface PlacedBox { id: string; label: string; kind: "node" | "topic"; column: number; row: number }

/** Columns from left to right: publishers, their topics, subscribers, ... (longest path from a source). */
export function layoutTopology(topology: Topology): PlacedBox[] {
  const ids = [...topology.nodes.map((n) => n.name), ...topology.topics.map((t) => t.name)];
  const rank = new Map(ids.map((id) => [id, 0]));
  for (let pass = 0; pass < ids.length; pass++) {
    let changed = false;
    for (const edge of topology.edges) {
      const next = (rank.get(edge.from) ?? 0) + 1;
      if (next > (rank.get(edge.to) ?? 0) && next < ids.length * 2) {
        rank.set(edge.to, next);
        changed = true;
      }
    }
    if (!changed) break;
  }
  const rows = new Map<number, number>();
  const topicNames = new Set(topology.topics.map((t) => t.name));
  return ids.map((id) => {
    const column = rank.get(id) ?? 0;
    const row = rows.get(column) ?? 0;
    rows.set(column, row + 1);
    return { id, label: id, kind: topicNames.has(id) ? "topic" : "node", column, row };
  });
}

/** The robot's nodes and topics as a graph, with each topic's live rate and each node's process state. */
export function TopologyGraph({ topology, rates, nodes }: {
  topology: Topology; rates: Record<string, number>; nodes: NodeStatus[];
}) {
  const boxes = layoutTopology(topology);
  const position = new Map(boxes.map((box) => [box.id, box]));
  const processOf = new Map(topology.nodes.map((node) => [node.name, node.process]));
  const stateOf = new Map(nodes.map((node) => [node.name, node.state]));
  const columns = Math.max(1, ...boxes.map((b) => b.column + 1));
  const rows = Math.max(1, ...boxes.map((b) => b.row + 1));
  const x = (box: PlacedBox) => 10 + box.column * COLUMN_WIDTH;
  const y = (box: PlacedBox) => 10 + box.row * ROW_HEIGHT;
  return (
    <div className="overflow-x-auto" data-scrolls="sideways">
    <svg viewBox={`0 0 ${columns * COLUMN_WIDTH} ${rows * ROW_HEIGHT + 10}`} className="w-full" role="img"
         style={{ maxWidth: columns * COLUMN_WIDTH, minWidth: Math.min(columns * COLUMN_WIDTH, MIN_READABLE_WIDTH) }}
         aria-label="topology">
      {topology.edges.map((edge) => {
        const from = position.get(edge.from), to = position.get(edge.to);
        if (!from || !to) return null;
        const x1 = x(from) + BOX_WIDTH, y1 = y(from) + BOX_HEIGHT / 2, x2 = x(to), y2 = y(to) + BOX_HEIGHT / 2;
        const bend = (x2 - x1) / 2;
        return <path key={`${edge.from}->${edge.to}`} d={`M${x1},${y1} C${x1 + bend},${y1} ${x2 - bend},${y2} ${x2},${y2}`}
                     fill="none" stroke="#475569" strokeWidth={1.5} markerEnd="url(#arrow)" />;
      })}
      <defs>
        <marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="6" markerHeight="6" orient="auto">
          <path d="M0,0 L10,5 L0,10 z" fill="#64748b" />
        </marker>
      </defs>
      {boxes.map((box) => {
        const isTopic = box.kind === "topic";
        const state = isTopic ? undefined : stateOf.get(processOf.get(box.id) ?? box.id);
        const stroke = isTopic ? "#6366f1" : STATE_STROKE[state ?? ""] ?? "#64748b";
        return (
          <g key={box.id} transform={`translate(${x(box)},${y(box)})`} data-testid={`graph-${box.kind}-${box.id}`}>
            <rect width={BOX_WIDTH} height={BOX_HEIGHT} rx={isTopic ? 20 : 8} fill={isTopic ? "#1e1b4b" : "#0f172a"}
                  stroke={stroke} strokeWidth={1.5} />
            <text x={10} y={16} fill="#e2e8f0" fontSize={11} fontWeight={600}>{truncate(box.label, 24)}</text>
            <text x={10} y={31} fill="#94a3b8" fontSize={10}>
              {isTopic ? formatRate(rates[box.id]) : state ?? "—"}
            </text>
          </g>
        );
      })}
    </svg>
    </div>
  );
}

function truncate(text: string, length: number): string {
  return text.length > length ? `${text.slice(0, length - 1)}…` : text;
}
