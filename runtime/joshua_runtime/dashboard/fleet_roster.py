"""The robots the fleet view has heard from: the last valid status of each, at most MAX_ROBOTS of them.

A robot not heard from for `offline_after_s` is listed as offline; after `forget_after_s` it is removed.
While the roster is full a robot it does not know yet is turned away (the ones it knows keep
updating) until a silent one is forgotten, so memory stays bounded whatever peers publish. Each status
is kept as the compact JSON of its checked fields, one block of memory that is freed whole.
"""

import json
import threading
import time
from dataclasses import dataclass

from joshua_runtime.dashboard.fleet_status import RobotStatus

MAX_ROBOTS = 256
DEFAULT_OFFLINE_AFTER_S = 10.0  # a dashboard publishes its status every second
DEFAULT_FORGET_AFTER_S = 600.0
PRUNE_PERIOD_S = 1.0  # how often arriving statuses also sweep out the forgotten robots


@dataclass(frozen=True)
class Entry:
    fields: bytes  # `"nodes":[...],"url":...,"error":...` of the checked status, as the API shows them
    seen: float  # time.monotonic() of its arrival


class Roster:
    """Written by zenoh's callback thread, read by the HTTP server: every access holds the lock."""

    def __init__(self, offline_after_s=DEFAULT_OFFLINE_AFTER_S, forget_after_s=DEFAULT_FORGET_AFTER_S, clock=None):
        self.offline_after_s = offline_after_s
        self.forget_after_s = forget_after_s
        self.clock = clock or time.monotonic
        self._lock = threading.Lock()
        self._entries: dict[str, Entry] = {}
        self._last_prune = self.clock()

    def update(self, robot: str, status: RobotStatus) -> bool:
        """Keep `status` as `robot`'s latest; False when the roster is full and `robot` is new to it."""
        now = self.clock()
        entry = Entry(status.model_dump_json(exclude={"robot"}).encode()[1:-1], now)
        with self._lock:
            if now - self._last_prune >= PRUNE_PERIOD_S:
                self._prune(now)
            if robot not in self._entries and len(self._entries) >= MAX_ROBOTS:
                return False
            self._entries[robot] = entry
        return True

    def robots(self) -> list[dict]:
        """`[{"name", "last_seen_s", "online", "nodes", "url", "error"}]`, sorted by name."""
        return json.loads(self.robots_json())

    def robots_json(self) -> bytes:
        """robots() as the JSON the API answers, joined from the kept blocks without decoding them."""
        now = self.clock()
        with self._lock:
            self._prune(now)
            entries = sorted(self._entries.items())
        return b"[" + b",".join(self._entry_json(name, entry, now) for name, entry in entries) + b"]"

    def _entry_json(self, name: str, entry: Entry, now: float) -> bytes:
        age = now - entry.seen
        head = json.dumps({"name": name, "last_seen_s": round(age, 3), "online": age <= self.offline_after_s})
        return head[:-1].encode() + b"," + entry.fields + b"}"

    def __len__(self) -> int:
        with self._lock:
            return len(self._entries)

    def _prune(self, now: float) -> None:
        self._last_prune = now
        forgotten = [name for name, entry in self._entries.items() if now - entry.seen > self.forget_after_s]
        for name in forgotten:
            del self._entries[name]
