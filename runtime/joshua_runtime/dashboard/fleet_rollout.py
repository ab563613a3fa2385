"""The last rollout as the fleet view shows it, from `joshua-fleet deploy`'s state file (rollout/state.py).

The file is read again when it changed (size or modification time), at most MAX_STATE_BYTES of it, and
only its documented fields of the documented types are kept: `GET /api/rollout` answers the summary,
each robot of `GET /api/robots` the entries of its computers (`arm_1`, or `split.arm`, `split.pi`).
"""

import os
import threading
from pathlib import Path

from joshua_runtime.rollout.state import read_state

SUMMARY_FIELDS = {"fleet": str, "state": str, "started": str, "finished": str}
ROBOT_FIELDS = {"name": str, "release": str, "state": str, "step": str, "message": str, "rolled_back_to": str}
MAX_TEXT_CHARS = 1024


def _kept(record: dict, fields: dict) -> dict:
    kept = {}
    for name, kind in fields.items():
        value = record.get(name)
        kept[name] = value[:MAX_TEXT_CHARS] if isinstance(value, kind) else None
    return kept


def _seconds(value) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


class RolloutView:
    """What the fleet view knows of the last rollout; safe to call from the HTTP server's threads."""

    def __init__(self, path: Path | None):
        self.path = path
        self._lock = threading.Lock()
        self._seen: tuple | None = None
        self._summary: dict | None = None
        self._robots: dict[str, list[dict]] = {}

    def _refresh(self) -> None:
        try:
            status = os.stat(self.path) if self.path else None
        except OSError:
            status = None
        seen = (status.st_mtime_ns, status.st_size) if status else None
        if seen == self._seen:
            return
        document = read_state(self.path) if status else None
        self._seen, self._summary, self._robots = seen, None, {}
        if not isinstance(document, dict):
            return
        self._summary = _kept(document, SUMMARY_FIELDS)
        for record in document.get("robots") or []:
            if not isinstance(record, dict) or not isinstance(record.get("name"), str):
                continue
            entry = {**_kept(record, ROBOT_FIELDS), "seconds": _seconds(record.get("seconds"))}
            robot = entry["name"].split(".", 1)[0]  # the robot of one of its hosts' entries
            self._robots.setdefault(robot, []).append(entry)

    def summary(self) -> dict | None:
        with self._lock:
            self._refresh()
            return self._summary

    def by_robot(self) -> dict[str, list[dict]]:
        with self._lock:
            self._refresh()
            return dict(self._robots)
