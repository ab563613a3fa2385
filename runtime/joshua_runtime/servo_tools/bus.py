"""Open a serial port as a register-level STS3215 bus for the bench tools, naming who holds a busy port."""

import os
from contextlib import contextmanager
from pathlib import Path

from joshua_runtime.drivers.sts3215 import DEFAULT_BAUD_RATE, Sts3215Driver
from joshua_runtime.drivers.sts3215_transport import PortBusy

TOOL_REPLY_TIMEOUT_S = 0.1  # generous: a bench tool waits for a slow adapter rather than report a false absence
TOOL_RETRIES = 1  # asks twice, then reports


def port_holders(port: str, locks_file: str = "/proc/locks") -> list[str]:
    """`name (pid N)` of each process holding a flock on `port` (the lock pyserial's exclusive open takes)."""
    try:
        info = os.stat(port)
        text = Path(locks_file).read_text()
    except OSError:
        return []
    wanted = f"{os.major(info.st_dev):02x}:{os.minor(info.st_dev):02x}:{info.st_ino}"
    holders = []
    for line in text.splitlines():
        fields = line.split()
        if len(fields) >= 6 and fields[1] == "FLOCK" and fields[5] == wanted:
            pid = fields[4]
            try:
                name = Path(f"/proc/{pid}/comm").read_text().strip()
            except OSError:
                name = "a process"
            holders.append(f"{name} (pid {pid})")
    return holders


@contextmanager
def open_bus(port: str, baud_rate: int = DEFAULT_BAUD_RATE, ids: list[int] | None = None):
    """A driver on `port` with no servo check, locked for this process; PortBusy names the holder."""
    bus = Sts3215Driver(
        port, list(ids or []), baud_rate=baud_rate, reply_timeout_s=TOOL_REPLY_TIMEOUT_S, max_retries=TOOL_RETRIES
    )
    try:
        bus.open()
    except PortBusy as exc:
        holders = port_holders(port)
        raise PortBusy(f"{exc}{': ' + ', '.join(holders) if holders else ''}") from None
    try:
        yield bus
    finally:
        bus.close()
