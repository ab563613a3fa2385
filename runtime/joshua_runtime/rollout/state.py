"""The rollout's progress in a JSON file, rewritten whole (a new file renamed over it) after every change, that
the fleet view reads (`joshua-fleet --rollout-state`) and `joshua-fleet rollback` takes the fleet from.

    {"fleet", "out", "state": "running" | "succeeded" | "failed", "started", "finished" (ISO 8601 or null),
     "robots": [{"name", "release", "state", "step", "message", "rolled_back_to", "seconds"}]}

A robot's state: waiting, deploying, updated (ready on its new release), failed (kept or rolled back to its
previous release: `rolled_back_to`), not_started (the rollout stopped first), rolled_back (by
`joshua-fleet rollback`).
"""

import json
import os
import tempfile
import time
from pathlib import Path

STATE_FILE = "rollout.json"
MAX_STATE_BYTES = 1024 * 1024  # 256 robots at most a few KiB each


def state_dir() -> Path:
    """$XDG_STATE_HOME/joshua/fleet, else ~/.local/state/joshua/fleet."""
    base = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return Path(base, "joshua", "fleet")


def default_state_path() -> Path:
    return state_dir() / STATE_FILE


def now_iso() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%S%z")


def read_state(path: Path) -> dict | None:
    """The rollout recorded at `path`, or None when there is none (or it is unreadable or too large)."""
    try:
        with open(path, "rb") as file:
            data = file.read(MAX_STATE_BYTES + 1)
        state = json.loads(data) if len(data) <= MAX_STATE_BYTES else None
    except (OSError, ValueError):
        return None
    return state if isinstance(state, dict) else None


class RolloutState:
    """The file's content, and the changes a rollout makes to it."""

    def __init__(self, path: Path, document: dict):
        self.path = Path(path)
        self.document = document

    @classmethod
    def begin(cls, path: Path, fleet: str, out: Path, robots: list) -> "RolloutState":
        robots_state = [
            {"name": r.name, "release": r.release, "state": "waiting", "step": "", "message": "",
             "rolled_back_to": "", "seconds": None}
            for r in robots
        ]  # fmt: skip
        document = {"fleet": fleet, "out": str(Path(out).resolve()), "state": "running", "started": now_iso(),
                    "finished": None, "robots": robots_state}  # fmt: skip
        state = cls(path, document)
        state.save()
        return state

    def robot(self, name: str) -> dict:
        return next(entry for entry in self.document["robots"] if entry["name"] == name)

    def update(self, name: str, **fields) -> None:
        self.robot(name).update(fields)
        self.save()

    def finish(self, succeeded: bool) -> None:
        self.document.update(state="succeeded" if succeeded else "failed", finished=now_iso())
        self.save()

    def save(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, temporary = tempfile.mkstemp(prefix=f".{self.path.name}.", dir=self.path.parent)
        with os.fdopen(fd, "w", encoding="utf-8") as file:
            json.dump(self.document, file, indent=1)
        os.chmod(temporary, 0o644)
        os.replace(temporary, self.path)
