"""The dashboard process's log: one line per record on stderr, and a token bucket per kind of message, so
that a flood of one error (a client misbehaving thousands of times a second) costs a few lines and a count.

The supervisor keeps this output in the dashboard's log file and passes it on to its own stderr.
"""

import logging
import sys
import threading
import time
from collections import OrderedDict

BURST = 5  # records of one kind let through at once
REFILL_S = 10.0  # after the burst, one more record of that kind every this many seconds
MAX_KINDS = 1000  # kinds remembered; the least recently seen is forgotten beyond this
KIND_CHARS = 120  # the start of a message's first line that tells kinds apart
FORMAT = "dashboard: %(levelname)s: %(message)s"


class RateLimit(logging.Filter):
    """Lets through BURST records of each kind (logger, level, first line, exception type), then one per
    REFILL_S; the next record let through says how many similar ones were suppressed before it."""

    def __init__(self, burst: int = BURST, refill_s: float = REFILL_S, clock=time.monotonic):
        super().__init__()
        self.burst, self.refill_s, self.clock = burst, refill_s, clock
        self.kinds: OrderedDict[tuple, list] = OrderedDict()  # kind -> [tokens, time of last update, suppressed]
        self.lock = threading.Lock()

    def filter(self, record: logging.LogRecord) -> bool:
        kind = _kind(record)
        now = self.clock()
        with self.lock:
            tokens, last, suppressed = self.kinds.pop(kind, (self.burst, now, 0))
            tokens = min(self.burst, tokens + (now - last) / self.refill_s)
            if tokens < 1:
                self.kinds[kind] = [tokens, now, suppressed + 1]
                self._forget_old_kinds()
                return False
            self.kinds[kind] = [tokens - 1, now, 0]
            self._forget_old_kinds()
        if suppressed:
            record.msg = f"{record.getMessage()} [{suppressed} similar messages suppressed before this one]"
            record.args = None
        return True

    def pending(self) -> list[str]:
        """One line per kind with suppressed records not reported yet (for the end of the process)."""
        with self.lock:
            return [
                f"{count} similar messages suppressed: {kind[2]}" for kind, (_, _, count) in self.kinds.items() if count
            ]

    def _forget_old_kinds(self) -> None:
        while len(self.kinds) > MAX_KINDS:
            self.kinds.popitem(last=False)


def _kind(record: logging.LogRecord) -> tuple:
    try:
        message = record.getMessage()
    except (TypeError, ValueError):
        message = str(record.msg)
    exception = record.exc_info[0].__name__ if record.exc_info and record.exc_info[0] else ""
    return (record.name, record.levelno, message.split("\n", 1)[0][:KIND_CHARS], exception)


def configure_logging(level: int = logging.WARNING) -> RateLimit:
    """Route every logger of the process (uvicorn's, asyncio's, ours) through one rate-limited stderr
    handler; returns the filter, whose `pending()` the process reports before it exits."""
    limit = RateLimit()
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(FORMAT))
    handler.addFilter(limit)
    root = logging.getLogger()
    root.handlers[:] = [handler]
    root.setLevel(level)
    for name in ("uvicorn", "uvicorn.error", "uvicorn.access"):
        logging.getLogger(name).handlers[:] = []
        logging.getLogger(name).propagate = True
    return limit
