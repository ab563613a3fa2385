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

/** One connection to /api/events shared by every hook; reconnects after a drop. */
export class EventHub {
  private listeners = new Map<string, Set<Listener>>();
  private stopped = false;
  private abort: AbortController | null = null;
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
    if (!listeners || listeners.size === 0) return;
    const data = JSON.parse(event.data);
    listeners.forEach((listener) => listener(data));
  }

  start(): void {
    void this.loop();
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
