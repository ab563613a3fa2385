import { StrictMode, useEffect, useState } from "react";
import { createRoot } from "react-dom/client";
import { getJson } from "../api";
import "../index.css";
import { RobotList } from "./RobotList";
import { RolloutSummary } from "./RolloutSummary";
import { readRobots, readRollout, type FleetRobot, type FleetRollout } from "./robots";

const REFRESH_MS = 1000;

function FleetPage() {
  const [robots, setRobots] = useState<FleetRobot[]>([]);
  const [rollout, setRollout] = useState<FleetRollout | null>(null);
  const [error, setError] = useState<string | null>(null);
  useEffect(() => {
    const load = () => {
      getJson<unknown>("/api/robots").then(readRobots)
        .then((r) => { setRobots(r); setError(null); }, (e: Error) => setError(e.message));
      getJson<unknown>("/api/rollout").then(readRollout).then(setRollout, () => setRollout(null));
    };
    load();
    const timer = setInterval(load, REFRESH_MS);
    return () => clearInterval(timer);
  }, []);
  return (
    <div className="min-h-screen bg-slate-950 text-slate-200">
      <header className="border-b border-slate-800 bg-slate-900/80 px-6 py-3">
        <h1 className="text-lg font-semibold text-slate-100">Fleet</h1>
        <p className="text-xs text-slate-400">{robots.filter((r) => r.last_seen_s !== null).length} robots publishing</p>
        <RolloutSummary rollout={rollout} robots={robots} />
      </header>
      <main className="mx-auto max-w-[1600px] p-4">
        {error && <p className="mb-3 text-rose-300" role="alert">{error}</p>}
        <RobotList robots={robots} />
      </main>
    </div>
  );
}

createRoot(document.getElementById("root")!).render(<StrictMode><FleetPage /></StrictMode>);
