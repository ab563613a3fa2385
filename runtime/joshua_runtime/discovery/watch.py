"""Watch a host's Discovery Server: say within 5 s that it does not answer, retry with back-off, say when it is back.

    python -m joshua_runtime.discovery.watch --server 10.0.0.1:11811 [--server-id 0]

The rule (`ServerWatch`, a pure state machine; the command runs it with probe.py):
- While the server answers, it is probed every HEALTHY_PERIOD_S.
- When a probe finds no answer, probes follow every RETRY_PERIOD_S; once no probe has been answered for
  UNREACHABLE_AFTER_S the server is declared unreachable. A server that never answered is declared so
  UNREACHABLE_AFTER_S after the first probe; one that stops answering, at most HEALTHY_PERIOD_S +
  UNREACHABLE_AFTER_S (5 s) after its last answer.
- While unreachable, probes back off: BACKOFF_S, doubled after each unanswered probe up to BACKOFF_MAX_S.
  The first answer makes it reachable again and resets the back-off.

The command prints one line per change of state and tells its process manager through sd_notify
(notify.py): READY=1 the first time the server answers, and on every change STATUS=<that line> and
DISCOVERY_SERVER=reachable|unreachable, a field the supervisor can show in `ctl status`. It exits 0 on
SIGINT or SIGTERM.
"""

import argparse
import signal
import sys
import threading
import time
from dataclasses import dataclass

from joshua_runtime.discovery import probe as server_probe
from joshua_runtime.notify import Notifier

HEALTHY_PERIOD_S = 2.0
RETRY_PERIOD_S = 0.5
UNREACHABLE_AFTER_S = 3.0
BACKOFF_S = 1.0
BACKOFF_MAX_S = 30.0
PROBING, REACHABLE, UNREACHABLE = "probing", "reachable", "unreachable"
STATE_FIELD = "DISCOVERY_SERVER"


@dataclass(frozen=True)
class Change:
    state: str
    line: str


class ServerWatch:
    """When to probe next and what the probes mean; `record(result, now)` returns a Change or None."""

    def __init__(self, where: str, now_s: float):
        self.where = where
        self.state = PROBING
        self.since_s = now_s  # when the current state began
        self.last_answer_s: float | None = None
        self.silent_since_s: float | None = None  # the first unanswered probe since the last answer
        self.unanswered = 0
        self.backoff_s = BACKOFF_S
        self.next_probe_s = now_s
        self.last_detail = ""

    def record(self, result: server_probe.ProbeResult, now_s: float) -> Change | None:
        self.last_detail = result.detail
        if result.answered:
            return self._answered(result, now_s)
        return self._unanswered(result, now_s)

    def _answered(self, result, now_s: float) -> Change | None:
        was, outage_s = self.state, now_s - (self.silent_since_s or now_s)
        self.last_answer_s, self.silent_since_s, self.unanswered, self.backoff_s = now_s, None, 0, BACKOFF_S
        self.next_probe_s = now_s + HEALTHY_PERIOD_S
        if was == REACHABLE:
            return None
        self.state, self.since_s = REACHABLE, now_s
        if was == UNREACHABLE:
            return Change(
                REACHABLE, f"discovery server {self.where} answers again after {outage_s:.1f} s: {result.detail}"
            )
        return Change(REACHABLE, f"discovery server {self.where} reachable: {result.detail}")

    def _unanswered(self, result, now_s: float) -> Change | None:
        self.unanswered += 1
        if self.silent_since_s is None:
            self.silent_since_s = now_s
        if self.state == UNREACHABLE:
            self.backoff_s = min(2 * self.backoff_s, BACKOFF_MAX_S)
            self.next_probe_s = now_s + self.backoff_s
            return None
        reference = self.last_answer_s if self.last_answer_s is not None else self.since_s
        if now_s - reference < UNREACHABLE_AFTER_S:
            self.next_probe_s = now_s + RETRY_PERIOD_S
            return None
        self.state, self.since_s = UNREACHABLE, now_s
        self.next_probe_s = now_s + self.backoff_s
        return Change(
            UNREACHABLE,
            f"discovery server {self.where} unreachable: {result.detail} ({self.unanswered} probes unanswered in "
            f"{now_s - self.silent_since_s:.1f} s); nodes on this host cannot discover the others; "
            f"retrying with back-off up to every {BACKOFF_MAX_S:g} s",
        )


def run(
    address: str, port: int, server_id: int | None, stop: threading.Event, notifier: Notifier, out=sys.stdout
) -> int:
    """Probe until `stop` is set, printing and notifying each change; exit code 0."""
    watch = ServerWatch(f"{address}:{port}", time.monotonic())
    announced_ready = False
    while not stop.is_set():
        result = server_probe.probe(address, port, server_id)
        change = watch.record(result, time.monotonic())
        if change is not None:
            print(change.line, file=out, flush=True)
            fields = [f"STATUS={change.line}", f"{STATE_FIELD}={change.state}"]
            if change.state == REACHABLE and not announced_ready:
                fields.insert(0, "READY=1")
                announced_ready = True
            notifier.send(*fields)
        stop.wait(max(0.0, watch.next_probe_s - time.monotonic()))
    notifier.stopping()
    return 0


def _arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m joshua_runtime.discovery.watch", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--server", required=True, metavar="ADDRESS:PORT", help="the Discovery Server's UDP locator")
    parser.add_argument("--server-id", type=int, default=None, help="the id the server must have (its -i)")
    args = parser.parse_args(argv)
    address, _, port = args.server.rpartition(":")
    if not address or not port.isdigit() or not 0 < int(port) < 65536:
        parser.error(f"--server {args.server!r} is not ADDRESS:PORT")
    args.address, args.port = address, int(port)
    return args


def main(argv: list[str] | None = None) -> int:
    args = _arguments(argv)
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    return run(args.address, args.port, args.server_id, stop, Notifier.from_environment())


if __name__ == "__main__":
    sys.exit(main())
