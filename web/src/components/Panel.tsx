import type { ReactNode } from "react";

/** A titled card that holds one part of the page. */
export function Panel({ title, aside, children, className = "" }: {
  title: string; aside?: ReactNode; children: ReactNode; className?: string;
}) {
  return (
    <section className={`min-w-0 rounded-xl border border-slate-800 bg-slate-900/70 shadow-sm ${className}`} aria-label={title}>
      <header className="flex flex-wrap items-center justify-between gap-x-3 gap-y-1 border-b border-slate-800 px-3 py-2.5 sm:px-4">
        <h2 className="min-w-0 break-all text-sm font-semibold tracking-wide text-slate-200">{title}</h2>
        {aside && <div className="text-xs text-slate-400">{aside}</div>}
      </header>
      <div className="p-3 sm:p-4">{children}</div>
    </section>
  );
}

export function EmptyNote({ children }: { children: ReactNode }) {
  return <p className="py-6 text-center text-sm text-slate-500">{children}</p>;
}
