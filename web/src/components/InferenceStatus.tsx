import { useInferenceStatus } from "../hooks/streams";
import { formatRate } from "../format";
import type { InferenceInfo } from "../types";
import { Panel } from "./Panel";

/** An inference node's model, its measured action rate, and which inputs are stale. */
export function InferenceStatus({ info }: { info: InferenceInfo }) {
  const status = useInferenceStatus(info.node);
  const stale = status?.stale_inputs ?? info.inputs;
  return (
    <Panel title={`Inference · ${info.node}`}>
      <dl className="grid grid-cols-[auto_1fr] gap-x-4 gap-y-1.5 text-sm">
        <dt className="text-slate-500">Model</dt>
        <dd className="truncate font-mono text-xs text-slate-200" title={info.model}>{info.model || "—"}</dd>
        <dt className="text-slate-500">Actions</dt>
        <dd className="text-slate-200" data-testid={`inference-rate-${info.node}`}>
          {formatRate(status?.rate_hz)} <span className="text-slate-500">of {formatRate(info.rate_hz)}</span>
        </dd>
        <dt className="text-slate-500">Inputs</dt>
        <dd className="flex flex-wrap gap-1.5">
          {info.inputs.map((input) => (
            <span key={input} className={`rounded px-1.5 py-0.5 font-mono text-xs ${stale.includes(input)
              ? "bg-amber-500/15 text-amber-300" : "bg-emerald-500/15 text-emerald-300"}`}>
              {input}{stale.includes(input) ? " · stale" : ""}
            </span>
          ))}
        </dd>
      </dl>
    </Panel>
  );
}
