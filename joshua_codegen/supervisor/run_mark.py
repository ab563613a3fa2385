"""Which run this is: a random id, the start time and the build, told in a header line at each start."""

import hashlib
import os
import time

from joshua_codegen.supervisor.common import SCRIPT_DIR
from joshua_codegen.supervisor.robot import ROBOT

RUN_ID_BYTES = 4  # a run id is this many random bytes in hex: 8 digits
BUILD_SHOWN_DIGITS = 12  # of the build's hash, in the header line (status --json gives all 64)
RUN_HEADER_START = "-- run "  # how a run's header line begins, in the supervisor's output and each node's log


def log_time(wall: float) -> str:
    """`wall` (seconds since the epoch) in ISO 8601 with milliseconds and the local offset, as
    `2025-06-01T14:03:27.512+02:00` (the offset of TZ, else of /etc/localtime)."""
    seconds = int(wall)
    local = time.localtime(seconds)
    sign = "-" if local.tm_gmtoff < 0 else "+"
    hours, minutes = divmod(abs(local.tm_gmtoff) // 60, 60)
    millis = min(999, int((wall - seconds) * 1000))
    return f"{time.strftime('%Y-%m-%dT%H:%M:%S', local)}.{millis:03d}{sign}{hours:02d}:{minutes:02d}"


def build_stamp() -> tuple[str, float | None]:
    """The SHA-256 of the build's stamp beside supervisor.py (what `sha256sum OUT/.joshuac-stamp` prints: the
    stamp lists every file of the build with its own hash) and the stamp's modification time (when the build
    was written; copies that keep times keep it), or ("", None) when there is none to read."""
    try:
        with open(os.path.join(SCRIPT_DIR, ROBOT["stamp_file"]), "rb") as stamp:
            return hashlib.sha256(stamp.read()).hexdigest(), os.fstat(stamp.fileno()).st_mtime
    except OSError:
        return "", None


class RunMark:
    """This start of the supervisor: its run id, when it started (wall clock) and which build it runs."""

    def __init__(self):
        self.id = os.urandom(RUN_ID_BYTES).hex()
        self.started = time.time()
        self.build, self.built = build_stamp()
        self.pid = os.getpid()

    def header(self) -> str:
        """The line that begins the run in the supervisor's output and in every node's log file."""
        build = self.build[:BUILD_SHOWN_DIGITS] or f"unknown (no {ROBOT['stamp_file']} beside supervisor.py)"
        return (
            f"{RUN_HEADER_START}{self.id}: robot {ROBOT['name']}, build {build}, supervisor pid {self.pid}, "
            f"started {log_time(self.started)} --"
        )

    def as_dict(self) -> dict:
        """The run in `status` replies: {"id", "started" (ISO 8601), "build" (64 hex digits, or null), "built"
        (when the build's stamp was written, ISO 8601, or null)}."""
        built = log_time(self.built) if self.built is not None else None
        return {"id": self.id, "started": log_time(self.started), "build": self.build or None, "built": built}
