import * as Dialog from "@radix-ui/react-dialog";
import { useEffect, useRef } from "react";
import { useNodeLog } from "../hooks/streams";

/** The tail of one node's log, refreshed while open. */
export function LogDialog({ node, onClose }: { node: string | null; onClose: () => void }) {
  const log = useNodeLog(node ?? "", node !== null);
  const end = useRef<HTMLDivElement>(null);
  useEffect(() => {
    // A block, not an arrow's value: scrollIntoView returns a Promise in recent browsers, and React
    // would call whatever an effect returns as its clean-up.
    end.current?.scrollIntoView?.({ block: "end" });
  }, [log.lines]);
  return (
    <Dialog.Root open={node !== null} onOpenChange={(open) => !open && onClose()}>
      <Dialog.Portal>
        <Dialog.Overlay className="fixed inset-0 bg-black/60" />
        <Dialog.Content className="fixed left-1/2 top-1/2 flex max-h-[80vh] w-[min(900px,92vw)] -translate-x-1/2 -translate-y-1/2 flex-col rounded-xl border border-slate-700 bg-slate-900 shadow-2xl">
          <div className="flex items-center justify-between gap-2 border-b border-slate-800 px-4 py-3">
            <Dialog.Title className="min-w-0 break-all text-sm font-semibold text-slate-100">Log of {node}</Dialog.Title>
            <Dialog.Close className="rounded-md px-2 py-1 text-sm text-slate-400 hover:bg-slate-800" data-testid="log-close">
              Close
            </Dialog.Close>
          </div>
          <Dialog.Description className="sr-only">The last lines this process wrote</Dialog.Description>
          <pre className="flex-1 overflow-auto p-4 font-mono text-xs leading-relaxed text-slate-300" data-testid="log-lines"
               data-loads={log.loads}>
            {log.lines.join("\n") || (log.error ? "" : "no output yet")}
            <div ref={end} />
          </pre>
          {log.error && <p className="px-4 pb-3 text-sm text-rose-300" role="alert">{log.error}</p>}
        </Dialog.Content>
      </Dialog.Portal>
    </Dialog.Root>
  );
}
