// The one SSE connection of the page, shared by the stream hooks through React context.
import { createContext, useContext, useEffect, useState, type ReactNode } from "react";
import { authHeaders } from "../api";
import { EventHub, type Listener } from "../sse";
import type { ServerEvents } from "../types";

const HubContext = createContext<EventHub | null>(null);

/** How often shown ages move on, and how often the plots are drawn again. */
export const AGE_TICK_MS = 250;

/** Holds the page's event stream; it connects once a component asks for it (useEventStream). */
export function EventHubProvider({ hub, children }: { hub?: EventHub; children: ReactNode }) {
  const [value] = useState(() => hub ?? new EventHub("/api/events", authHeaders));
  useEffect(() => (hub ? undefined : () => value.stop()), [hub, value]);
  return <HubContext.Provider value={value}>{children}</HubContext.Provider>;
}

/** Connects the event stream once `enabled` (the robot answered with this tab's token: a stream
 * opened without it would only be refused). */
export function useEventStream(enabled: boolean): void {
  const hub = useContext(HubContext);
  useEffect(() => {
    if (enabled) hub?.start();
  }, [hub, enabled]);
}

/** The server's clock (seconds, Unix time) at the last of its ticks, every `periodMs` while the component is
 * mounted: the same value until the next tick, however often the component is drawn meanwhile. */
export function useServerTick(periodMs = AGE_TICK_MS): number {
  const hub = useContext(HubContext);
  const [now, setNow] = useState(() => serverNow(hub));
  useEffect(() => {
    const timer = setInterval(() => setNow(serverNow(hub)), periodMs);
    return () => clearInterval(timer);
  }, [hub, periodMs]);
  return now;
}

/** The server's clock (seconds, Unix time) as the component is drawn, which happens at least every `periodMs`
 * while it is mounted. */
export function useServerNow(periodMs = AGE_TICK_MS): number {
  const hub = useContext(HubContext);
  useServerTick(periodMs);
  return serverNow(hub);
}

function serverNow(hub: EventHub | null): number {
  return hub ? hub.serverNow() : Date.now() / 1000;
}

/** Calls `listener` with every event of `kind` (an event of the API's schema) while the component is mounted. */
export function useEventListener(kind: keyof ServerEvents, listener: Listener): void {
  const hub = useContext(HubContext);
  useEffect(() => (hub ? hub.on(kind, listener) : undefined), [hub, kind, listener]);
}

/** Whether the event stream is connected. */
export function useConnected(): boolean {
  const hub = useContext(HubContext);
  const [connected, setConnected] = useState(hub?.connected ?? false);
  useEffect(() => {
    if (!hub) return;
    hub.onConnection = setConnected;
    return () => { hub.onConnection = null; };
  }, [hub]);
  return connected;
}

/** The latest event of `kind` whose `key` field equals `value` (or the latest of all when no key). */
export function useLatest<K extends keyof ServerEvents, T extends object = ServerEvents[K]>(
  kind: K, key?: keyof T, value?: unknown,
): T | null {
  const [latest, setLatest] = useState<T | null>(null);
  const listener = useKeyedListener<T>(key, value, setLatest);
  useEventListener(kind, listener);
  return latest;
}

function useKeyedListener<T>(key: keyof T | undefined, value: unknown, set: (event: T) => void): Listener {
  const [listener] = useState<{ current: Listener }>(() => ({ current: () => {} }));
  listener.current = (data) => {
    if (key === undefined || (data as T)[key] === value) set(data as T);
  };
  const [stable] = useState<Listener>(() => (data: unknown) => listener.current(data));
  return stable;
}
