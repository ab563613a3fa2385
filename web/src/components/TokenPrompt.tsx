import { useState, type FormEvent } from "react";
import { apiToken, storeApiToken } from "../api";

/** Asks for the dashboard's access token when the robot refused the one this tab has (or it has none). */
export function TokenPrompt({ onToken }: { onToken: () => void }) {
  const [token, setToken] = useState("");
  const refused = apiToken() !== null;
  function submit(event: FormEvent) {
    event.preventDefault();
    if (!token.trim()) return;
    storeApiToken(token);
    onToken();
  }
  return (
    <div className="grid min-h-screen place-items-center bg-slate-950 p-8 text-slate-200">
      <form onSubmit={submit} className="w-full max-w-lg space-y-4 rounded-xl border border-slate-800 bg-slate-900/70 p-6"
            data-testid="token-prompt">
        <h1 className="text-lg font-semibold text-slate-100">This robot's dashboard needs its access token</h1>
        {refused && <p className="text-sm text-rose-300" role="alert">The token this tab had was refused.</p>}
        <p className="text-sm text-slate-400">
          Open the address <code>joshuac run</code> printed (it carries the token), or paste the token from the
          file <code>ROBOT.dashboard-token</code> beside the robot's control socket.
        </p>
        <input type="password" value={token} onChange={(e) => setToken(e.target.value)} autoComplete="off"
               aria-label="Access token" data-testid="token-input"
               className="w-full rounded-md border border-slate-700 bg-slate-950 px-3 py-2 font-mono text-sm" />
        <button type="submit" data-testid="token-submit"
                className="rounded-md bg-indigo-500 px-3 py-1.5 text-sm font-medium text-white hover:bg-indigo-400">
          Open the dashboard
        </button>
      </form>
    </div>
  );
}
