"""Which serial device is the servo adapter: compare the devices before and after the user (un)plugs it."""

import glob
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass

DEVICE_PATTERNS = ("/dev/ttyUSB*", "/dev/ttyACM*", "/dev/ttyAMA*", "/dev/ttyS*", "/dev/serial/by-id/*")
POLL_INTERVAL_S = 0.1


@dataclass(frozen=True)
class PortChange:
    appeared: list[str]
    vanished: list[str]

    def describe(self) -> str:
        parts = [
            f"appeared: {' '.join(self.appeared)}" if self.appeared else "",
            f"vanished: {' '.join(self.vanished)}" if self.vanished else "",
        ]
        return "; ".join(part for part in parts if part) or "no serial device changed"


def list_devices(patterns: Iterable[str] = DEVICE_PATTERNS) -> set[str]:
    """Serial device paths present now."""
    return {path for pattern in patterns for path in glob.glob(pattern)}


def compare(before: set[str], after: set[str]) -> PortChange:
    return PortChange(appeared=sorted(after - before), vanished=sorted(before - after))


def find_port_interactive(lister: Callable[[], set[str]], ask: Callable[[str], str]) -> PortChange:
    """Snapshot, ask the user to unplug (or plug) the adapter, snapshot again."""
    before = lister()
    ask("Unplug the servo adapter's USB cable (or plug it in), then press Enter: ")
    return compare(before, lister())


def watch_for_change(lister: Callable[[], set[str]], timeout_s: float) -> PortChange:
    """Poll until a device appears or vanishes, or `timeout_s` passes (then the change is empty)."""
    before = lister()
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        time.sleep(POLL_INTERVAL_S)
        change = compare(before, lister())
        if change.appeared or change.vanished:
            return change
    return PortChange([], [])
