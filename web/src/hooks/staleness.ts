// How old the newest message of a stream is, on the server's clock, and whether it counts as stale.
import type { Stamped } from "../types";
import { useServerNow } from "./EventHubContext";

export interface Staleness { ageS: number; stale: boolean }

/** The age of `event` at `serverNow`; stale once older than `staleAfterS` (null: nothing received yet). */
export function staleness(event: Stamped | null, staleAfterS: number, serverNow: number): Staleness | null {
  if (!event) return null;
  const ageS = Math.max(0, serverNow - event.server_time_s);
  return { ageS, stale: ageS > staleAfterS };
}

/** staleness() of `event`, kept up to date as time passes. */
export function useStaleness(event: Stamped | null, staleAfterS: number): Staleness | null {
  return staleness(event, staleAfterS, useServerNow());
}
