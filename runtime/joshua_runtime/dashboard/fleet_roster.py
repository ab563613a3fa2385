"""The robots the fleet view has heard from: the last valid status of each, at most MAX_ROBOTS of them.

A robot not heard from for `offline_after_s`, or whose status was withdrawn (its dashboard stopped), is listed
as offline until its next status; after `forget_after_s` without one it is removed.
While the roster is full a robot it does not know yet is turned away (the ones it knows keep
updating) until a silent one is forgotten, so memory stays bounded whatever peers publish. Each status
is kept as the compact JSON of its checked fields, one block of memory that is freed whole.
"""

import json
import threading
import time
from dataclasses import dataclass, replace

from joshua_runtime.dashboard.fleet_status import RobotStatus

MAX_ROBOTS = 256
DEFAULT_OFFLINE_AFTER_S = 10.0  # a dashboard publishes its status every second
DEFAULT_FORGET_AFTER_S = 600.0
PRUNE_PERIOD_S = 1.0  # how often arriving statuses also sweep out the forgotten robots
RELEASE_DIGITS = 12  # of a build's hash, as the supervisor and the rollout show it


def listed_fields(status: RobotStatus) -> bytes:
    """`"nodes":[...],"url":...,"error":...,"release":...,"health":...` of a checked status: its release (the
    build's first RELEASE_DIGITS hex digits and time) and how many of its nodes are ready."""
    run = status.run
    release = {"build": run.build[:RELEASE_DIGITS], "built": run.built} if run and run.build else None
    health = {"ready": sum(1 for node in status.nodes if node.ready), "of": len(status.nodes)}
    shown = status.model_dump(mode="json", exclude={"robot", "run"})
    return json.dumps({**shown, "release": release, "health": health}, separators=(",", ":")).encode()[1:-1]


NOT_HEARD_FROM = listed_fields(RobotStatus())


@dataclass(frozen=True)
class Entry:
    fields: bytes  # listed_fields() of the checked status, as the API shows them
    seen: float  # time.monotonic() of its arrival
    withdrawn: bool = False  # the robot deleted its status since: offline whatever its age


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
        entry = Entry(listed_fields(status), now)
        with self._lock:
            if now - self._last_prune >= PRUNE_PERIOD_S:
                self._prune(now)
            if robot not in self._entries and len(self._entries) >= MAX_ROBOTS:
                return False
            self._entries[robot] = entry
        return True

    def withdraw(self, robot: str) -> None:
        """`robot` withdrew its status: list it offline, with what it said last, until it publishes again."""
        with self._lock:
            entry = self._entries.get(robot)
            if entry is not None:
                self._entries[robot] = replace(entry, withdrawn=True)

    def robots(self, rollouts: dict[str, list] | None = None) -> list[dict]:
        """`[{"name", "last_seen_s", "online", "nodes", "url", "error", "release", "health", "rollout"}]`, sorted by
        name; `rollouts` (robot -> its computers' entries in the last rollout) adds robots not heard from."""
        return json.loads(self.robots_json(rollouts))

    def robots_json(self, rollouts: dict[str, list] | None = None) -> bytes:
        """robots() as the JSON the API answers, joined from the kept blocks without decoding them."""
        now = self.clock()
        rollouts = rollouts or {}
        with self._lock:
            self._prune(now)
            entries = dict(self._entries)
        names = sorted(set(entries) | set(rollouts))
        listed = (self._entry_json(name, entries.get(name), rollouts.get(name), now) for name in names)
        return b"[" + b",".join(listed) + b"]"

    def _entry_json(self, name: str, entry: Entry | None, rollout: list | None, now: float) -> bytes:
        if entry is None:  # a robot of the rollout that publishes nothing
            head = {"name": name, "last_seen_s": None, "online": False}
            fields = NOT_HEARD_FROM
        else:
            age = now - entry.seen
            online = not entry.withdrawn and age <= self.offline_after_s
            head = {"name": name, "last_seen_s": round(age, 3), "online": online}
            fields = entry.fields
        tail = json.dumps(rollout, separators=(",", ":")).encode()
        return json.dumps(head)[:-1].encode() + b"," + fields + b',"rollout":' + tail + b"}"

    def __len__(self) -> int:
        with self._lock:
            return len(self._entries)

    def _prune(self, now: float) -> None:
        self._last_prune = now
        forgotten = [name for name, entry in self._entries.items() if now - entry.seen > self.forget_after_s]
        for name in forgotten:
            del self._entries[name]
