// Server-Sent Events read through fetch (so the Authorization header can be sent), parsed by hand.

export interface ServerEvent {
  kind: string;
  data: string;
}

/** Splits a buffer into complete events; returns them and the unfinished rest. */
export function parseEvents(buffer: string): { events: ServerEvent[]; rest: string } {
  const events: ServerEvent[] = [];
  const blocks = buffer.split("\n\n");
  const rest = blocks.pop() ?? "";
  for (const block of blocks) {
    let kind = "message";
    const data: string[] = [];
    for (const line of block.split("\n")) {
      if (line.startsWith("event:")) kind = line.slice(6).trim();
      else if (line.startsWith("data:")) data.push(line.slice(5).replace(/^ /, ""));
    }
    if (data.length > 0) events.push({ kind, data: data.join("\n") });
  }
  return { events, rest };
}

export type Listener = (data: unknown) => void;

/** The event with the server's clock, sent on connection and every second after. */
export const CLOCK_EVENT = "clock";

/** One connection to /api/events shared by every hook; reconnects after a drop. It also keeps the
 * difference between the server's clock and this browser's, so that ages are measured on the server's. */
export class EventHub {
  private listeners = new Map<string, Set<Listener>>();
  private stopped = false;
  private running = false;
  private abort: AbortController | null = null;
  private clockOffsetS = 0;
  connected = false;
  onConnection: ((connected: boolean) => void) | null = null;

  constructor(private url: string, private headers: () => Record<string, string>, private retryMs = 1000) {}

  on(kind: string, listener: Listener): () => void {
    if (!this.listeners.has(kind)) this.listeners.set(kind, new Set());
    this.listeners.get(kind)!.add(listener);
    return () => this.listeners.get(kind)?.delete(listener);
  }

  dispatch(event: ServerEvent): void {
    const listeners = this.listeners.get(event.kind);
    if (event.kind !== CLOCK_EVENT && (!listeners || listeners.size === 0)) return;
    const data = JSON.parse(event.data);
    if (event.kind === CLOCK_EVENT) this.clockOffsetS = data.server_time_s - Date.now() / 1000;
    listeners?.forEach((listener) => listener(data));
  }

  /** The server's clock now, in seconds (Unix time), as far as its last clock event tells. */
  serverNow(): number {
    return Date.now() / 1000 + this.clockOffsetS;
  }

  /** Connects (once; a second call while connected does nothing). */
  start(): void {
    this.stopped = false;
    if (this.running) return;
    this.running = true;
    void this.loop().finally(() => { this.running = false; });
  }

  stop(): void {
    this.stopped = true;
    this.abort?.abort();
  }

  private setConnected(connected: boolean): void {
    this.connected = connected;
    this.onConnection?.(connected);
  }

  private async loop(): Promise<void> {
    while (!this.stopped) {
      try {
        this.abort = new AbortController();
        const response = await fetch(this.url, { headers: this.headers(), signal: this.abort.signal, cache: "no-store" });
        if (!response.ok || !response.body) throw new Error(`${response.status}`);
        this.setConnected(true);
        const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
        let buffer = "";
        for (;;) {
          const { value, done } = await reader.read();
          if (done) break;
          const parsed = parseEvents(buffer + value);
          buffer = parsed.rest;
          parsed.events.forEach((event) => this.dispatch(event));
        }
      } catch {
        // dropped or refused: try again below
      }
      this.setConnected(false);
      if (!this.stopped) await new Promise((resolve) => setTimeout(resolve, this.retryMs));
    }
  }
}
