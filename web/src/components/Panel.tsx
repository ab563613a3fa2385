import type { ReactNode } from "react";

/** A titled card that holds one part of the page. */
export function Panel({ title, aside, children, className = "" }: {
  title: string; aside?: ReactNode; children: ReactNode; className?: string;
}) {
  return (
    <section className={`rounded-xl border border-slate-800 bg-slate-900/70 shadow-sm ${className}`} aria-label={title}>
      <header className="flex items-center justify-between border-b border-slate-800 px-4 py-2.5">
        <h2 className="text-sm font-semibold tracking-wide text-slate-200">{title}</h2>
        {aside && <div className="text-xs text-slate-400">{aside}</div>}
      </header>
      <div className="p-4">{children}</div>
    </section>
  );
}

export function EmptyNote({ children }: { children: ReactNode }) {
  return <p className="py-6 text-center text-sm text-slate-500">{children}</p>;
}
