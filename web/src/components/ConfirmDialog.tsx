import * as Dialog from "@radix-ui/react-dialog";
import type { Confirmation } from "../nodeActions";

/** Asks before an action that cannot simply be taken back; `onAnswer(true)` to go ahead. */
export function ConfirmDialog({ question, onAnswer }: {
  question: Confirmation | null; onAnswer: (yes: boolean) => void;
}) {
  return (
    <Dialog.Root open={question !== null} onOpenChange={(open) => !open && onAnswer(false)}>
      <Dialog.Portal>
        <Dialog.Overlay className="fixed inset-0 bg-black/60" />
        <Dialog.Content role="alertdialog" data-testid="confirm-dialog"
                        className="fixed left-1/2 top-1/2 w-[min(480px,92vw)] -translate-x-1/2 -translate-y-1/2 space-y-3 rounded-xl border border-slate-700 bg-slate-900 p-5 shadow-2xl">
          <Dialog.Title className="break-words text-base font-semibold text-slate-100">{question?.title}</Dialog.Title>
          <Dialog.Description className="text-sm text-slate-300">{question?.detail}</Dialog.Description>
          <div className="flex flex-wrap justify-end gap-2 pt-2">
            <button type="button" onClick={() => onAnswer(false)} data-testid="confirm-cancel"
                    className="rounded-md border border-slate-700 px-3 py-1.5 text-sm text-slate-200 hover:bg-slate-800">
              Cancel
            </button>
            <button type="button" onClick={() => onAnswer(true)} data-testid="confirm-action"
                    className="rounded-md bg-rose-600 px-3 py-1.5 text-sm font-medium text-white hover:bg-rose-500">
              {question?.action}
            </button>
          </div>
        </Dialog.Content>
      </Dialog.Portal>
    </Dialog.Root>
  );
}
