import { describe, expect, it } from "vitest";
import { parseEvents } from "../sse";

describe("parseEvents", () => {
  it("splits complete events and keeps the unfinished rest", () => {
    const { events, rest } = parseEvents('retry: 1000\n\nevent: status\ndata: {"a":1}\n\nevent: rates\ndata: {"r');
    expect(events).toEqual([{ kind: "status", data: '{"a":1}' }]);
    expect(rest).toBe('event: rates\ndata: {"r');
  });

  it("ignores keepalive comments", () => {
    expect(parseEvents(": keepalive\n\n").events).toEqual([]);
  });
});
