"""LDS-01 lidar emulator on a pseudo-terminal: streams the synthetic room at the device's real pace.

Silent until it reads ASCII `b` (motor start); then sends 42-byte packets, 60 per turn, one packet
every 1/rpm minute (300 packets/s, 12,600 bytes/s at 300 rpm) on an absolute schedule, until it
reads `e` (motor stop). Like a real UART, bytes the host does not read in time are lost: writes
never block, and whatever the pty buffer cannot take is dropped.

Corrupted packets (for the driver's sanity checks) either carry an index byte outside 0xA0-0xDB
or a zero speed field; their checksum no longer matches either.
"""

import fcntl
import os
import random
import select
import threading
import time

from joshua_runtime.drivers import lds01_protocol as proto
from joshua_runtime.drivers import synthetic_room
from joshua_runtime.emulators.pty_link import PtyLink

POLL_S = 0.02  # longest wait between two checks of the stop flag
MAX_LAG_PACKETS = proto.PACKETS_PER_TURN  # beyond this lag, restart the schedule instead of bursting
STOP_JOIN_TIMEOUT_S = 2.0
BAD_INDEX_BASE = proto.FIRST_INDEX + proto.PACKETS_PER_TURN  # 0xDC: never a valid index byte


class Lds01Stream:
    """The device behaviour on a pty master fd: command parsing and the packet schedule."""

    def __init__(
        self,
        fd: int,
        rpm: float = proto.NOMINAL_RPM,
        corrupt_rate: float = 0.0,
        seed: int = 0,
        corrupt_packets: frozenset[int] = frozenset(),
    ):
        if rpm <= 0:
            raise ValueError("rpm must be positive")
        self.fd = fd
        self.rpm = rpm
        self.corrupt_rate = corrupt_rate
        self.corrupt_packets = frozenset(corrupt_packets)
        self._rng = random.Random(seed)
        self._packet_period_s = 60.0 / (rpm * proto.PACKETS_PER_TURN)
        self._speed = int(round(rpm * proto.SPEED_SCALE))
        self._clean = self._clean_turn()
        self.spinning = False
        self.packets_sent = 0
        self.packets_corrupted = 0
        self.bytes_dropped = 0
        self._next_index = 0
        self._next_time = 0.0
        flags = fcntl.fcntl(fd, fcntl.F_GETFL)
        fcntl.fcntl(fd, fcntl.F_SETFL, flags | os.O_NONBLOCK)

    def _clean_turn(self) -> list[bytes]:
        ranges = synthetic_room.scan_mm()
        packets = []
        for k in range(proto.PACKETS_PER_TURN):
            readings = []
            for j in range(proto.READINGS_PER_PACKET):
                mm = ranges[proto.scan_index(k, j)]
                readings.append((synthetic_room.intensity(mm), mm))
            packets.append(proto.encode_packet(k, self._speed, readings))
        return packets

    def _corrupted(self, packet: bytes, bad_index: bool) -> bytes:
        damaged = bytearray(packet)
        if bad_index:
            damaged[1] = BAD_INDEX_BASE + self._rng.randrange(0x100 - BAD_INDEX_BASE)
        else:
            damaged[2] = damaged[3] = 0
        return bytes(damaged)

    def _packet(self, k: int) -> bytes:
        packet = self._clean[k]
        if k in self.corrupt_packets:
            self.packets_corrupted += 1
            return self._corrupted(packet, bad_index=k % 2 == 0)
        if self.corrupt_rate > 0 and self._rng.random() < self.corrupt_rate:
            self.packets_corrupted += 1
            return self._corrupted(packet, bad_index=self._rng.random() < 0.5)
        return packet

    def _write(self, data: bytes) -> None:
        try:
            written = os.write(self.fd, data)
        except BlockingIOError:
            written = 0
        self.bytes_dropped += len(data) - written

    def _handle_commands(self, data: bytes) -> None:
        for byte in data:
            command = bytes((byte,))
            if command == proto.START_COMMAND and not self.spinning:
                self.spinning = True
                self._next_index = 0
                self._next_time = time.monotonic()
            elif command == proto.STOP_COMMAND:
                self.spinning = False

    def _send_due_packets(self) -> None:
        now = time.monotonic()
        if now - self._next_time > MAX_LAG_PACKETS * self._packet_period_s:
            self._next_time = now
        while self.spinning and self._next_time <= now:
            self._write(self._packet(self._next_index))
            self.packets_sent += 1
            self._next_index = (self._next_index + 1) % proto.PACKETS_PER_TURN
            self._next_time += self._packet_period_s

    def run(self, should_stop) -> None:
        """Serve until `should_stop()` is true."""
        while not should_stop():
            wait = POLL_S
            if self.spinning:
                wait = min(POLL_S, max(0.0, self._next_time - time.monotonic()))
            readable, _, _ = select.select([self.fd], [], [], wait)
            if readable:
                try:
                    data = os.read(self.fd, 4096)
                except (BlockingIOError, InterruptedError):
                    data = b""
                self._handle_commands(data)
            if self.spinning:
                self._send_due_packets()


def serve(args, should_stop) -> None:
    """`joshua-emulate lds01`: args has .link, .rpm, .corrupt_rate, .seed."""
    with PtyLink(args.link) as link:
        Lds01Stream(link.master_fd, rpm=args.rpm, corrupt_rate=args.corrupt_rate, seed=args.seed).run(should_stop)


class Lds01Emulator:
    """The emulator on a background thread, for tests: `with Lds01Emulator(link) as emu: ...`."""

    def __init__(
        self,
        link,
        rpm: float = proto.NOMINAL_RPM,
        corrupt_rate: float = 0.0,
        seed: int = 0,
        corrupt_packets=frozenset(),
    ):
        self.link = link
        self._options = dict(rpm=rpm, corrupt_rate=corrupt_rate, seed=seed, corrupt_packets=frozenset(corrupt_packets))
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._pty: PtyLink | None = None
        self.stream: Lds01Stream | None = None

    def start(self) -> "Lds01Emulator":
        self._pty = PtyLink(self.link)
        self.stream = Lds01Stream(self._pty.master_fd, **self._options)
        self._stop.clear()
        self._thread = threading.Thread(
            target=self.stream.run, args=(self._stop.is_set,), daemon=True, name="lds01-emulator"
        )
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(STOP_JOIN_TIMEOUT_S)
            self._thread = None
        if self._pty is not None:
            self._pty.close()
            self._pty = None

    def __enter__(self) -> "Lds01Emulator":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
