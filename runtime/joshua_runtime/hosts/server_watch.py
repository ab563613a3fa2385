"""The agent's watch of the robot's Discovery Server: probes in a thread, each change told to the supervisor.

discovery/watch.py decides when to probe and what the probes mean (unreachable at most 5 s after the last
answer, then probes backing off up to every 30 s, reachable at the first answer); here each change is
printed as one line and sent to the supervisor as `DISCOVERY_SERVER=reachable|unreachable` with the line as
`STATUS=`, which `supervisor.py ctl status` shows as "discovery".
"""

import threading
import time

from joshua_runtime.discovery import probe as server_probe
from joshua_runtime.discovery.watch import STATE_FIELD, ServerWatch


class DiscoveryWatch:
    def __init__(self, address: str, port: int, notifier, out):
        self.address, self.port = address, port
        self.notifier, self.out = notifier, out
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, name="discovery-watch", daemon=True)

    def start(self) -> None:
        self.thread.start()

    def _run(self) -> None:
        watch = ServerWatch(f"{self.address}:{self.port}", time.monotonic())
        while not self.stop.is_set():
            change = watch.record(server_probe.probe(self.address, self.port), time.monotonic())
            if change is not None:
                print(change.line, file=self.out, flush=True)
                self.notifier.send(f"STATUS={change.line}", f"{STATE_FIELD}={change.state}")
            self.stop.wait(max(0.0, watch.next_probe_s - time.monotonic()))

    def close(self) -> None:
        self.stop.set()
