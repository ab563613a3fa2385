"""The JSON lines of a running dds_probe (or any line-printing process), gathered by a reader thread."""

import json
import subprocess
import threading
import time

POLL_S = 0.05


class ProbeOutput:
    """Every JSON event a process printed so far (`events`), its other lines (`text`), and waits on them."""

    def __init__(self, process: subprocess.Popen):
        self.process = process
        self.events: list[dict] = []
        self.text: list[str] = []
        self._lock = threading.Lock()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.process.stdout:
            try:
                event = json.loads(line)
            except ValueError:
                event = None
            with self._lock:
                if isinstance(event, dict) and "event" in event:
                    self.events.append(event)
                else:
                    self.text.append(line)

    def of(self, kind: str) -> list[dict]:
        with self._lock:
            return [event for event in self.events if event["event"] == kind]

    def wait_for(self, condition, timeout_s: float) -> bool:
        """Wait until `condition(self)` holds or the process ended; whether it held within `timeout_s`."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if condition(self):
                return True
            if self.process.poll() is not None:
                self._reader.join(1.0)
                return condition(self)
            time.sleep(POLL_S)
        return condition(self)

    def received_seqs(self) -> list[int]:
        return [event["seq"] for event in self.of("received")]

    def last_graph(self) -> dict:
        graphs = self.of("graph")
        return graphs[-1] if graphs else {"nodes": [], "topics": []}

    def lines(self) -> list[str]:
        """The lines printed so far that were not events."""
        with self._lock:
            return list(self.text)

    def tail(self, lines: int = 30) -> str:
        """The end of what the process printed besides events (for assertion messages)."""
        with self._lock:
            return "".join(self.text[-lines:])
