"""Fan-out of events to browser clients, each through a bounded mailbox that keeps only the newest event per key.

A key names one stream (`joints:/leader/joint_states`, `image:/camera/image_raw`, `status`): a client
that reads slower than a stream publishes gets the newest frame and skips the ones in between, so a
stalled browser holds at most one event per key and never slows the publisher or grows memory.
Every event carries `server_time_s`, the server's clock (Unix time) when it was published: for a
stream, when its message arrived, so the page can tell how old what it shows is.
"""

import asyncio
import json
import time
from collections import OrderedDict
from typing import NamedTuple

# Events as compact JSON; NaN and infinities are refused (frames.py turns them into null).
_JSON = json.JSONEncoder(separators=(",", ":"), allow_nan=False)


class Mailbox:
    """One client's pending events: at most one per key, oldest key first. Used from the event loop only."""

    def __init__(self):
        self._pending: OrderedDict[str, Event] = OrderedDict()
        self._waiter: asyncio.Future | None = None
        self.dropped = 0

    def put(self, key: str, payload: "Event") -> None:
        if key in self._pending:
            self.dropped += 1
            del self._pending[key]
        self._pending[key] = payload
        self.wake()

    def wake(self) -> None:
        """End a `wait` under way (an event came, or the reader must look at something else)."""
        waiter = self._waiter
        if waiter is not None and not waiter.done():
            waiter.set_result(None)

    async def wait(self, timeout: float | None = None) -> bool:
        """Wait until an event is pending (True), or until `timeout` passes or `wake()` (False when none is)."""
        if not self._pending:
            loop = asyncio.get_running_loop()
            self._waiter = waiter = loop.create_future()
            timer = loop.call_later(timeout, _end_wait, waiter) if timeout is not None else None
            try:
                await waiter
            finally:
                self._waiter = None
                if timer is not None:
                    timer.cancel()
        return bool(self._pending)

    async def get(self) -> "Event":
        """The oldest pending event (waits for one)."""
        return (await self.get_with_key())[1]

    async def get_with_key(self) -> tuple[str, "Event"]:
        """The oldest pending event with its key (waits for one)."""
        while not await self.wait():
            pass
        return self._pending.popitem(last=False)

    def take_all(self) -> list["Event"]:
        """Every pending event, oldest first, without waiting (none pending: an empty list)."""
        events = list(self._pending.values())
        self._pending.clear()
        return events

    def pending_bytes(self) -> int:
        return sum(len(event.data) for event in self._pending.values())


def _end_wait(waiter: asyncio.Future) -> None:
    if not waiter.done():
        waiter.set_result(None)


class Event(NamedTuple):
    """One event: its kind (the SSE event name), its data as JSON text and as Server-Sent Event bytes."""

    kind: str
    data: str
    sse: bytes  # `event: KIND` and the JSON data on one line, encoded once for every client

    @classmethod
    def of(cls, kind: str, data: str) -> "Event":
        """The event of `kind` with `data` (JSON text on one line)."""
        return cls(kind, data, f"event: {kind}\ndata: {data}\n\n".encode())


class Broadcaster:
    """Owns the clients' mailboxes; `publish` may be called from any thread once the server's loop is attached."""

    def __init__(self):
        self.loop: asyncio.AbstractEventLoop | None = None
        self.mailboxes: set[Mailbox] = set()
        self.viewers: set[Mailbox] = set()
        # The newest event per key, replayed to a client when it connects (the page can reload any time).
        self.latest: dict[str, Event] = {}

    @property
    def client_count(self) -> int:
        """How many browsers are connected (mailboxes of forwarders such as the fleet link do not count)."""
        return len(self.viewers)

    def subscribe(self, viewer: bool = True) -> Mailbox:
        """A new mailbox, primed with the newest event of every key; `viewer`: it serves a browser."""
        mailbox = Mailbox()
        for key, payload in self.latest.items():
            mailbox.put(key, payload)
        self.mailboxes.add(mailbox)
        if viewer:
            self.viewers.add(mailbox)
        return mailbox

    def unsubscribe(self, mailbox: Mailbox) -> None:
        self.mailboxes.discard(mailbox)
        self.viewers.discard(mailbox)

    def wake_all(self) -> None:
        """End every mailbox's `wait` under way (called from the event loop's thread)."""
        for mailbox in self.mailboxes:
            mailbox.wake()

    def attach(self, loop: asyncio.AbstractEventLoop) -> None:
        """Deliver events in `loop` (the server's) from now on; events published before are dropped."""
        self.loop = loop

    def publish(self, key: str, kind: str, data: dict) -> None:
        """Queue an event for every client (thread-safe); it replaces an unsent event of the same key."""
        loop = self.loop
        if loop is None or loop.is_closed():
            return
        stamped = {**data, "server_time_s": round(time.time(), 3)}
        payload = Event.of(kind, _JSON.encode(stamped))
        try:
            loop.call_soon_threadsafe(self._deliver, key, payload)
        except RuntimeError:  # the server is shutting down
            pass

    def _deliver(self, key: str, payload: Event) -> None:
        self.latest[key] = payload
        for mailbox in self.mailboxes:
            mailbox.put(key, payload)
