"""The serial side of an STS3215 bus: send instruction packets, collect status packets, retry.

A transaction writes one instruction and waits for the status packets it should produce. A missing
reply (none within REPLY_TIMEOUT_S plus the reply's time on the wire, nor in the input buffer when
this thread next runs after that deadline) or a reply with a bad checksum makes it try again, up to
`max_retries` more times, after discarding whatever is left in the input buffer. Bytes
that never frame a packet (two servos answering at once) count as a garbled reply. The port is
locked with flock on open, so a second program opening it gets PortBusy. A vanished port closes the
transport and raises DeviceError; the owner reopens it later.
"""

import errno
import os
import select
import termios
import time
from collections import Counter
from dataclasses import dataclass

import serial

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.errors import DeviceError

REPLY_TIMEOUT_S = 0.02  # beyond a reply's transmission time; above an FTDI adapter's 16 ms latency timer
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


class PortBusy(DeviceError):
    """Another program holds the serial port."""


class NoAnswer(DeviceError):
    """A servo sent nothing back, on every attempt."""


class GarbledReply(DeviceError):
    """Replies arrived but never framed a packet: usually two servos sharing one id."""


class CorruptReply(DeviceError):
    """Replies framed but failed their checksum or had the wrong size."""


class _NoAnswer(Exception):
    def __init__(self, servo_id: int):
        self.servo_id = servo_id


class _Corrupt(_NoAnswer):
    pass


class _Garbled(_NoAnswer):
    pass


_FAILURES = {  # attempt failure -> (stats key, error raised after the last attempt, what it says)
    _Garbled: ("garbled", GarbledReply, "garbled replies from"),
    _Corrupt: ("checksum_errors", CorruptReply, "corrupt replies from"),
    _NoAnswer: ("timeouts", NoAnswer, "no answer from"),
}


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
            if getattr(exc, "errno", None) in (errno.EAGAIN, errno.EWOULDBLOCK, errno.EBUSY):
                raise PortBusy(f"serial port {self.port} is busy: another program has it open") from None
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

    def set_baud_rate(self, baud_rate: int) -> None:
        """Switch the line speed (the port stays open)."""
        self.baud_rate = baud_rate
        if self._serial is not None:
            try:
                self._serial.baudrate = baud_rate
            except (serial.SerialException, OSError, ValueError, termios.error) as exc:
                self._lost(exc)

    def collect(self, packet: bytes, quiet_s: float) -> tuple[list[proto.Packet], bool]:
        """Write `packet` and gather every status packet: wait the reply timeout for the first byte,
        then stop once the line stays quiet for `quiet_s`.

        Returns the well-formed packets and whether any bytes failed to frame one (a collision).
        """
        self._write(packet)
        packets, garbled = [], False
        discarded_before = self._parser.discarded
        wait_s = self.reply_timeout_s
        while True:
            data = self._read_some(wait_s + STATUS_OVERHEAD_BYTES * BITS_PER_BYTE / self.baud_rate)
            wait_s = quiet_s
            if not data:
                return packets, garbled or self._parser.pending > 0 or self._parser.discarded > discarded_before
            self._parser.feed(data)
            while (found := self._parser.pop()) is not None:
                if found.checksum_ok:
                    packets.append(found)
                else:
                    garbled = True

    def send(self, packet: bytes) -> None:
        """Write a packet that has no reply (SYNC_WRITE, broadcast)."""
        self._write(packet, discard_input=False)

    def transact(self, packet: bytes, expected: list[Expected]) -> list[proto.Packet]:
        """Write `packet` and return its status packets in order, retrying timeouts and bad checksums."""
        attempts = 1 + self.max_retries
        failure: _NoAnswer | None = None
        for attempt in range(attempts):
            if attempt:
                self.stats["retries"] += 1
            self._write(packet)
            try:
                return [self._receive(item) for item in expected]
            except _NoAnswer as exc:
                self.stats[_FAILURES[type(exc)][0]] += 1
                failure = exc
        _, error, what = _FAILURES[type(failure)]
        raise error(f"{self.port}: {what} servo id {failure.servo_id} after {attempts} attempts")

    def _write(self, packet: bytes, discard_input: bool = True) -> None:
        """Write one packet; before a transaction, drop unread bytes (late replies to earlier requests)."""
        if self._serial is None:
            raise DeviceError(f"serial port {self.port} is not open")
        try:
            if discard_input:
                self._serial.reset_input_buffer()
                self._parser.clear()
            self._queue(packet)
        except (serial.SerialException, OSError, termios.error) as exc:
            self._lost(exc)

    def _queue(self, packet: bytes) -> None:
        """Hand every byte to the kernel, waiting at most WRITE_TIMEOUT_S for room in its buffer.

        pyserial's write() also calls it a timeout when this thread was only kept off the CPU that long
        after its bytes went through, and a busy computer then took a working port for a dead one.
        """
        fd = self._serial.fileno()  # non-blocking, as pyserial opens it
        pending = memoryview(packet)
        deadline = time.monotonic() + WRITE_TIMEOUT_S
        while pending:
            try:
                pending = pending[os.write(fd, pending) :]
            except BlockingIOError:
                _, room, _ = select.select([], [fd], [], max(deadline - time.monotonic(), 0.0))
                if not room:
                    raise serial.SerialTimeoutException("Write timeout") from None

    def _receive(self, item: Expected) -> proto.Packet:
        reply_bytes = STATUS_OVERHEAD_BYTES + item.param_bytes
        deadline = time.monotonic() + self.reply_timeout_s + reply_bytes * BITS_PER_BYTE / self.baud_rate
        discarded_before = self._parser.discarded
        looked_after_deadline = False
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
            if looked_after_deadline:
                garbled = self._parser.pending or self._parser.discarded > discarded_before
                raise (_Garbled if garbled else _NoAnswer)(item.servo_id)
            # Past the deadline, one last look: a reply that came in time is in the buffer even when
            # this thread was kept off the CPU until after the deadline.
            remaining = deadline - time.monotonic()
            looked_after_deadline = remaining <= 0
            self._parser.feed(self._read_some(max(remaining, 0.0)))

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
