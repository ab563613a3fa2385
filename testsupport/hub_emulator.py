"""`joshua-emulate pybricks` as a process a test can restart, kill and pause, its output kept in a file.

Restarting it on the same port is what a re-plugged Bluetooth dongle looks like to a base node: the
HCI link closes, and a fresh controller answers on the same address again.
"""

import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

EMULATOR_START_TIMEOUT_S = 20.0
EMULATOR_STOP_TIMEOUT_S = 5.0
LOG_POLL_S = 0.02
READY_LINE = "reachable over hci tcp-client:127.0.0.1:"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def wait_for_text(path: Path, pattern: str, timeout_s: float, start: int = 0) -> re.Match | None:
    """The first match of `pattern` in the file from character `start` on, waiting up to `timeout_s`; None then."""
    deadline = time.monotonic() + timeout_s
    while True:
        text = path.read_text(errors="replace") if path.exists() else ""
        found = re.compile(pattern, re.M).search(text, start)
        if found or time.monotonic() > deadline:
            return found
        time.sleep(LOG_POLL_S)


class HubEmulator:
    """One emulated hub serving its HCI on 127.0.0.1:`port`, restartable; every run appends to `log_path`."""

    def __init__(self, directory: Path, *options: str, port: int | None = None):
        self.port = port or free_port()
        self.options = options
        self.log_path = directory / f"emulator-{self.port}.log"
        self.process: subprocess.Popen | None = None

    @property
    def hci(self) -> str:
        return f"tcp-client:127.0.0.1:{self.port}"

    def log(self) -> str:
        return self.log_path.read_text(errors="replace") if self.log_path.exists() else ""

    def start(self) -> "HubEmulator":
        offset = len(self.log())
        with open(self.log_path, "a") as log:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "joshua_runtime.emulators.cli", "pybricks", "--port", str(self.port)]
                + list(self.options),
                stdout=log,
                stderr=subprocess.STDOUT,
                env={**os.environ, "PYTHONUNBUFFERED": "1"},
            )
        if wait_for_text(self.log_path, re.escape(READY_LINE), EMULATOR_START_TIMEOUT_S, offset) is None:
            self.stop()
            raise AssertionError(f"joshua-emulate pybricks did not come up:\n{self.log()}")
        return self

    def stop(self, signum: int = signal.SIGINT) -> int | None:
        """End the emulator with `signum` (SIGKILL: a dongle pulled out); its exit code."""
        if self.process is None:
            return None
        process, self.process = self.process, None
        if process.poll() is None:
            os.kill(process.pid, signal.SIGCONT)  # a paused emulator cannot act on SIGINT
            process.send_signal(signum)
        try:
            return process.wait(EMULATOR_STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            return process.wait()

    def pause(self) -> None:
        """Freeze the emulator (SIGSTOP): the link stays up and nothing answers on it."""
        self.process.send_signal(signal.SIGSTOP)

    def resume(self) -> None:
        self.process.send_signal(signal.SIGCONT)

    def __enter__(self) -> "HubEmulator":
        return self.start()

    def __exit__(self, *exc_info) -> None:
        self.stop()
