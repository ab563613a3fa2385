"""The serial side of an STS3215 bus: send instruction packets, collect status packets, retry.

A transaction writes one instruction and waits for the status packets it should produce. A missing
reply (REPLY_TIMEOUT_S plus the reply's time on the wire) or a reply with a bad checksum makes it try
again, up to `max_retries` more times, after discarding whatever is left in the input buffer. A
vanished port closes the transport and raises DeviceError; the owner reopens it later.
"""

import os
import select
import termios
import time
from collections import Counter
from dataclasses import dataclass

import serial

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.errors import DeviceError

REPLY_TIMEOUT_S = 0.02  # wait for a status packet beyond its own transmission time
MAX_RETRIES = 3  # extra attempts after a timeout or a corrupt reply
WRITE_TIMEOUT_S = 0.1  # a write that cannot be queued in this time means a dead port
READ_CHUNK_BYTES = 512
BITS_PER_BYTE = 10  # 8N1
STATUS_OVERHEAD_BYTES = 6  # FF FF ID LEN ERR CHK


@dataclass(frozen=True)
class Expected:
    """One status packet a transaction waits for."""

    servo_id: int
    param_bytes: int


class _NoAnswer(Exception):
    def __init__(self, servo_id: int):
        self.servo_id = servo_id


class _Corrupt(Exception):
    def __init__(self, servo_id: int):
        self.servo_id = servo_id


class SerialTransport:
    """A serial port speaking the SCS protocol. `stats` counts timeouts, checksum errors and retries."""

    def __init__(
        self, port: str, baud_rate: int, reply_timeout_s: float = REPLY_TIMEOUT_S, max_retries: int = MAX_RETRIES
    ):
        self.port = port
        self.baud_rate = baud_rate
        self.reply_timeout_s = reply_timeout_s
        self.max_retries = max_retries
        self.stats = Counter()
        self.last_errors: dict[int, int] = {}  # servo id -> ERR byte of its latest status packet
        self._serial: serial.Serial | None = None
        self._parser = proto.PacketParser()

    @property
    def is_open(self) -> bool:
        return self._serial is not None

    def open(self) -> None:
        if self._serial is not None:
            return
        if not os.path.exists(self.port):
            raise DeviceError(f"serial port {self.port} not found")
        try:
            self._serial = serial.Serial(
                self.port, self.baud_rate, timeout=0, write_timeout=WRITE_TIMEOUT_S, exclusive=True
            )
        except (serial.SerialException, OSError, ValueError) as exc:
            raise DeviceError(f"cannot open serial port {self.port}: {_reason(exc)}") from None
        self._parser.clear()

    def close(self) -> None:
        if self._serial is None:
            return
        try:
            self._serial.close()
        except (serial.SerialException, OSError):
            pass
        self._serial = None

    def send(self, packet: bytes) -> None:
        """Write a packet that has no reply (SYNC_WRITE, broadcast)."""
        self._write(packet, discard_input=False)

    def transact(self, packet: bytes, expected: list[Expected]) -> list[proto.Packet]:
        """Write `packet` and return its status packets in order, retrying timeouts and bad checksums."""
        attempts = 1 + self.max_retries
        failure: Exception | None = None
        for attempt in range(attempts):
            if attempt:
                self.stats["retries"] += 1
            self._write(packet)
            try:
                return [self._receive(item) for item in expected]
            except _NoAnswer as exc:
                self.stats["timeouts"] += 1
                failure = exc
            except _Corrupt as exc:
                self.stats["checksum_errors"] += 1
                failure = exc
        what = "corrupt replies from" if isinstance(failure, _Corrupt) else "no answer from"
        raise DeviceError(f"{self.port}: {what} servo id {failure.servo_id} after {attempts} attempts")

    def _write(self, packet: bytes, discard_input: bool = True) -> None:
        """Write one packet; before a transaction, drop unread bytes (late replies to earlier requests)."""
        if self._serial is None:
            raise DeviceError(f"serial port {self.port} is not open")
        try:
            if discard_input:
                self._serial.reset_input_buffer()
                self._parser.clear()
            self._serial.write(packet)
        except (serial.SerialException, OSError, termios.error) as exc:
            self._lost(exc)

    def _receive(self, item: Expected) -> proto.Packet:
        reply_bytes = STATUS_OVERHEAD_BYTES + item.param_bytes
        deadline = time.monotonic() + self.reply_timeout_s + reply_bytes * BITS_PER_BYTE / self.baud_rate
        while True:
            packet = self._parser.pop()
            if packet is not None:
                if not packet.checksum_ok:
                    raise _Corrupt(item.servo_id)
                if packet.servo_id != item.servo_id:
                    continue  # a late answer to an earlier request
                if len(packet.params) != item.param_bytes:
                    raise _Corrupt(item.servo_id)
                self.last_errors[packet.servo_id] = packet.code
                return packet
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise _NoAnswer(item.servo_id)
            self._parser.feed(self._read_some(remaining))

    def _read_some(self, wait_s: float) -> bytes:
        try:
            ready, _, _ = select.select([self._serial.fileno()], [], [], wait_s)
            return self._serial.read(READ_CHUNK_BYTES) if ready else b""
        except (serial.SerialException, OSError, ValueError, termios.error) as exc:
            self._lost(exc)

    def _lost(self, exc: Exception):
        self.close()
        self.stats["disconnects"] += 1
        raise DeviceError(f"serial port {self.port} disconnected: {_reason(exc)}") from None


def _reason(exc: Exception) -> str:
    """The useful part of a pyserial/OS error message, on one line."""
    number = getattr(exc, "errno", None)
    if isinstance(exc, termios.error) and len(exc.args) == 2:
        number = exc.args[0]
    text = os.strerror(number) if isinstance(number, int) else str(exc) or type(exc).__name__
    return " ".join(text.split())
