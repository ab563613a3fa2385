"""A Feetech STS3215 servo bus emulated at the byte level on a pseudo-terminal.

    with Sts3215Emulator(tmp_path / "ttyLEADER", ids=[1, 2, 3]) as bus:
        bus.move_by_hand(1, 3000)          # turn servo 1 as a person would
        bus.read_register(2, "Goal_Position")

Only addressed packets are answered (PING also on broadcast); SYNC_READ replies come in request
order; SYNC_WRITE, ACTION on broadcast and restart are never answered; Response_Status_Level 0
limits replies to PING and READ. A servo hears only packets sent at the line speed its Baud_Rate
register selects (read from the pty's termios, as a UART is clocked). Two servos may share an id:
both answer, and their replies collide on the wire (`collide`). Garbage is skipped and a stalled partial frame is dropped after
PARTIAL_FRAME_TIMEOUT_S. Replies are delayed by their time on a wire at `baud_rate` plus the servo's
Return_Delay_Time, plus `adapter_latency_s` when a USB adapter's latency timer is modelled (an FTDI
chip holds a short reply 16 ms by default), and can be dropped or corrupted (bad checksum) at seeded
random rates or on demand.

Hardware answers within microseconds, whatever the computer is doing: the serving thread asks for
real-time scheduling (SCHED_FIFO, realtime.py, not inherited by forked children) so that a
busy machine does not delay its replies past a driver's reply timeout (bench/servo_replies.py). Without
the permission (CAP_SYS_NICE), or with realtime=False, it serves at normal priority.
"""

import copy
import os
import random
import select
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import (
    BAUD_RATE_CODES,
    MODEL_NUMBER_STS3215,
    TICKS_PER_TURN,
    encode_value,
    register,
)
from joshua_runtime.emulators.pty_link import PtyLink
from joshua_runtime.emulators.realtime import raise_to_realtime_priority
from joshua_runtime.emulators.sts3215_servo import EmulatedServo

DEFAULT_IDS = (1, 2, 3, 4, 5, 6)
DEFAULT_POSITION = 2048
POLL_INTERVAL_S = 0.05  # how often the serving thread checks for stop()
PARTIAL_FRAME_TIMEOUT_S = 0.02  # a frame silent this long mid-way is garbage
STOP_JOIN_TIMEOUT_S = 1.0
READ_CHUNK_BYTES = 4096
BITS_PER_BYTE = 10  # 8N1: start + 8 data + stop
RETURN_DELAY_UNIT_S = 2e-6
CORRUPTION_MASK = 0x5A  # XORed into the checksum byte of a corrupted reply

# Called from the serving thread after a write lands: (servo id, address, data, monotonic time).
WriteListener = Callable[[int, int, bytes, float], None]
# Called from the serving thread for each well-formed packet, before it runs: (packet, monotonic time).
PacketListener = Callable[[proto.Packet, float], None]


class Sts3215Emulator:
    """N emulated servos behind one pty at `link`; start() serves them from a background thread.

    `ids` may repeat an id (two servos wired with the same id); the in-process API then addresses
    the first of them, and `servos(id)` lists all.
    """

    def __init__(
        self,
        link: str | os.PathLike,
        ids=DEFAULT_IDS,
        *,
        drop_rate: float = 0.0,
        corrupt_rate: float = 0.0,
        seed: int = 0,
        baud_rate: int = 1_000_000,
        emulate_wire_time: bool = True,
        position: int = DEFAULT_POSITION,
        model_number: int = MODEL_NUMBER_STS3215,
        adapter_latency_s: float = 0.0,
        realtime: bool = True,
    ):
        self.link = Path(link)
        now = time.monotonic()
        if baud_rate not in BAUD_RATE_CODES:
            raise ValueError(f"STS3215 baud rates are {', '.join(map(str, BAUD_RATE_CODES))}, not {baud_rate}")
        code = BAUD_RATE_CODES[baud_rate]
        self._servos = [EmulatedServo(servo_id, position, now, model_number, code) for servo_id in ids]
        self.drop_rate = drop_rate
        self.corrupt_rate = corrupt_rate
        self.baud_rate = baud_rate
        self.emulate_wire_time = emulate_wire_time
        self.adapter_latency_s = adapter_latency_s
        self.realtime = realtime
        self.stats = Counter()  # packets, bad_checksums, replies, dropped, corrupted
        self.write_listeners: list[WriteListener] = []
        self.packet_listeners: list[PacketListener] = []
        self._random = random.Random(seed)
        self._forced = Counter()
        self._lock = threading.RLock()
        self._handled = threading.Condition(self._lock)
        self._pty: PtyLink | None = None
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()

    # --- lifecycle -------------------------------------------------------------------------
    def start(self) -> "Sts3215Emulator":
        """Create the pty at `link` and serve it. Can be called again after stop() (a re-plugged adapter)."""
        if self._thread is not None:
            return self
        self._pty = PtyLink(self.link)
        os.set_blocking(self._pty.master_fd, False)
        self._stop.clear()
        self._thread = threading.Thread(target=self._serve, name=f"sts3215@{self.link.name}", daemon=True)
        self._thread.start()
        return self

    def stop(self) -> None:
        """Stop serving and remove the pty, as unplugging the adapter would. Servo state is kept."""
        if self._thread is None:
            return
        self._stop.set()
        self._thread.join(STOP_JOIN_TIMEOUT_S)
        self._thread = None
        self._pty.close()
        self._pty = None

    @property
    def serving_thread_id(self) -> int | None:
        """The kernel's id of the thread that answers the bus, while serving."""
        return self._thread.native_id if self._thread else None

    @property
    def device_name(self) -> str | None:
        """The /dev/pts/N behind the link while serving."""
        return self._pty.slave_name if self._pty else None

    def __enter__(self) -> "Sts3215Emulator":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # --- in-process API --------------------------------------------------------------------
    @property
    def ids(self) -> list[int]:
        with self._lock:
            return sorted(servo.id for servo in self._servos)

    def servo(self, servo_id: int) -> EmulatedServo:
        """Direct access to one servo's state (call its methods only while the bus is idle)."""
        found = self.servos(servo_id)
        if not found:
            raise KeyError(f"no emulated servo with id {servo_id}")
        return found[0]

    def servos(self, servo_id: int) -> list[EmulatedServo]:
        """Every servo answering to `servo_id` (more than one when ids collide)."""
        return [servo for servo in self._servos if servo.id == servo_id]

    def snapshot(self) -> list[EmulatedServo]:
        """Copies of every servo's state, to carry the bus over to another process."""
        with self._lock:
            return copy.deepcopy(self._servos)

    def restore(self, servos: list[EmulatedServo]) -> None:
        """Take over servos from snapshot()."""
        with self._lock:
            self._servos = list(servos)
            self._handled.notify_all()

    def move_by_hand(self, servo_id: int, position: float) -> None:
        """Turn a servo's shaft to `position` ticks (present-position frame)."""
        with self._lock:
            self.servo(servo_id).move_by_hand(position, time.monotonic())
            self._handled.notify_all()

    def turn_shaft(self, servo_id: int, encoder_ticks: float) -> None:
        """Turn a servo's shaft so its encoder reads `encoder_ticks` before Homing_Offset is applied.

        This is the physical angle: two arms in the same pose give different encoder readings when
        their horns were mounted differently, and calibration exists to hide that.
        """
        with self._lock:
            servo = self.servo(servo_id)
            offset = servo.get("Homing_Offset")
            servo.move_by_hand((encoder_ticks - offset) % TICKS_PER_TURN, time.monotonic())
            self._handled.notify_all()

    def position(self, servo_id: int) -> int:
        return self.read_register(servo_id, "Present_Position")

    def read_register(self, servo_id: int, name: str) -> int:
        with self._lock:
            servo = self.servo(servo_id)
            servo.advance(time.monotonic())
            return servo.get(name)

    def write_register(self, servo_id: int, name: str, value: int) -> None:
        """Write a register as a WRITE instruction would (read-only registers: see set_sensor)."""
        reg = register(name)
        with self._lock:
            self.servo(servo_id).write(reg.address, encode_value(reg, value), time.monotonic())
            self._handled.notify_all()

    def set_sensor(self, servo_id: int, name: str, value: int) -> None:
        """Set Present_Voltage or Present_Temperature, e.g. to trigger the voltage or overheat bit."""
        with self._lock:
            self.servo(servo_id).set_sensor(name, value, time.monotonic())
            self._handled.notify_all()

    def inject_error(self, servo_id: int, bits: int) -> None:
        """Report these status error bits (e.g. proto.ERROR_OVERLOAD) until cleared with 0."""
        with self._lock:
            self.servo(servo_id).inject_errors(bits, time.monotonic())
            self._handled.notify_all()

    def drop_next_replies(self, count: int) -> None:
        with self._lock:
            self._forced["drop"] += count

    def corrupt_next_replies(self, count: int) -> None:
        with self._lock:
            self._forced["corrupt"] += count

    def wait_until(self, predicate: Callable[[], bool], timeout_s: float) -> bool:
        """Wait until `predicate()` holds, re-checked after every handled packet and API call."""
        deadline = time.monotonic() + timeout_s
        with self._handled:
            while not predicate():
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                self._handled.wait(min(remaining, POLL_INTERVAL_S))
            return True

    # --- serving ---------------------------------------------------------------------------
    def _serve(self) -> None:
        if self.realtime:
            raise_to_realtime_priority()
        fd = self._pty.master_fd
        parser = proto.PacketParser()
        last_byte_at = time.monotonic()
        while not self._stop.is_set():
            wait_s = PARTIAL_FRAME_TIMEOUT_S if parser.pending else POLL_INTERVAL_S
            readable, _, _ = select.select([fd], [], [], wait_s)
            now = time.monotonic()
            if readable:
                try:
                    data = os.read(fd, READ_CHUNK_BYTES)
                except (BlockingIOError, InterruptedError):
                    continue
                except OSError:
                    return
                parser.feed(data)
                last_byte_at = now
            elif parser.pending and now - last_byte_at >= PARTIAL_FRAME_TIMEOUT_S:
                parser.drop_byte()
            while (packet := parser.pop()) is not None:
                self._handle(fd, packet)

    def _handle(self, fd: int, packet: proto.Packet) -> None:
        with self._lock:
            self.stats["packets"] += 1
            if not packet.checksum_ok:
                self.stats["bad_checksums"] += 1
                return
            for listener in self.packet_listeners:
                listener(packet, time.monotonic())
            replies, delay_s = self._dispatch(packet)
            wire = b"".join(self._with_faults(reply) for reply in replies if reply)
            self._handled.notify_all()
        if not wire:
            return
        wait_s = self.adapter_latency_s
        if self.emulate_wire_time:
            wait_s += delay_s + (len(packet.raw) + len(wire)) * BITS_PER_BYTE / self.baud_rate
        if wait_s > 0:
            time.sleep(wait_s)
        try:
            os.write(fd, wire)
        except OSError:  # nobody reads the other side: the bytes are lost, as on a real bus
            pass

    def _listening(self) -> list[EmulatedServo]:
        """Servos clocked at the line's speed (all of them when the speed is unknown), by id."""
        speed = self._pty.line_speed() if self._pty else None
        code = BAUD_RATE_CODES.get(speed, -1) if speed else None
        servos = sorted(self._servos, key=lambda s: s.id)
        return [servo for servo in servos if code is None or servo.get("Baud_Rate") == code]

    def _dispatch(self, packet: proto.Packet) -> tuple[list[bytes], float]:
        """Execute one instruction packet; return the status packets to send and the return delay."""
        now = time.monotonic()
        code, params, target = packet.code, packet.params, packet.servo_id
        listening = self._listening()
        if code == proto.INST_SYNC_WRITE:
            if target == proto.BROADCAST_ID and len(params) >= 2:
                self._sync_write(listening, params[0], params[1], params[2:], now)
            return [], 0.0
        if code == proto.INST_SYNC_READ:
            if target != proto.BROADCAST_ID or len(params) < 2:
                return [], 0.0
            replies, answering = [], []
            for servo_id in params[2:]:
                servos = [s for s in listening if s.id == servo_id]
                answering += servos
                slot = [proto.encode(s.id, s.error_byte(), s.read(params[0], params[1], now)) for s in servos]
                replies.append(collide(slot))
            return replies, self._return_delay(answering)
        broadcast = target == proto.BROADCAST_ID
        replies, answering = [], []
        for servo in [s for s in listening if broadcast or s.id == target]:
            servo_id = servo.id  # a servo whose ID or status level is rewritten answers as before
            answers = self._answers(servo, code, broadcast)
            result = servo.execute(code, params, now)
            if code == proto.INST_WRITE and result is not None:
                self._notify_write(servo_id, params[0], bytes(params[1:]), now)
            if result is not None and answers:
                replies.append(proto.encode(servo_id, servo.error_byte(), result))
                answering.append(servo)
        if not broadcast:
            replies = [collide(replies)]
        return replies, self._return_delay(answering)

    def _sync_write(self, listening: list[EmulatedServo], address: int, size: int, blocks: bytes, now: float) -> None:
        for start in range(0, len(blocks) - size, size + 1):
            data = bytes(blocks[start + 1 : start + 1 + size])
            for servo in [s for s in listening if s.id == blocks[start]]:
                servo.write(address, data, now)
                self._notify_write(blocks[start], address, data, now)

    @staticmethod
    def _answers(servo: EmulatedServo, code: int, broadcast: bool) -> bool:
        if code == proto.INST_PING:
            return True
        if broadcast or code == proto.INST_RESTART:
            return False
        return code == proto.INST_READ or servo.get("Response_Status_Level") >= 1

    @staticmethod
    def _return_delay(servos: list[EmulatedServo]) -> float:
        return max((s.get("Return_Delay_Time") * RETURN_DELAY_UNIT_S for s in servos), default=0.0)

    def _notify_write(self, servo_id: int, address: int, data: bytes, now: float) -> None:
        for listener in self.write_listeners:
            listener(servo_id, address, data, now)

    def _with_faults(self, reply: bytes) -> bytes:
        self.stats["replies"] += 1
        if self._forced["drop"] or (self.drop_rate and self._random.random() < self.drop_rate):
            self._forced["drop"] = max(0, self._forced["drop"] - 1)
            self.stats["dropped"] += 1
            return b""
        if self._forced["corrupt"] or (self.corrupt_rate and self._random.random() < self.corrupt_rate):
            self._forced["corrupt"] = max(0, self._forced["corrupt"] - 1)
            self.stats["corrupted"] += 1
            return reply[:-1] + bytes([reply[-1] ^ CORRUPTION_MASK])
        return reply


def collide(replies: list[bytes]) -> bytes:
    """What the wire carries when these replies are sent at once.

    The line idles high and a driven 0 wins, so overlapping bytes AND together; the servos' clocks
    never line up exactly, so each further reply is modelled one byte later than the previous one.
    One reply passes unchanged; two identical ones still garble each other.
    """
    if len(replies) <= 1:
        return replies[0] if replies else b""
    width = max(len(reply) for reply in replies) + len(replies) - 1
    wire = bytearray(b"\xff" * width)
    for shift, reply in enumerate(replies):
        for index, value in enumerate(reply):
            wire[shift + index] &= value
    return bytes(wire)


def serve(args, should_stop: Callable[[], bool]) -> None:
    """`joshua-emulate sts3215`: serve args.ids on args.link until should_stop() is true."""
    emulator = Sts3215Emulator(
        args.link,
        args.ids,
        drop_rate=args.drop_rate,
        corrupt_rate=args.corrupt_rate,
        seed=args.seed,
        baud_rate=args.baud_rate,
    )
    with emulator:
        print(f"sts3215: servos {','.join(map(str, args.ids))} on {args.link} -> {emulator.device_name}", flush=True)
        if args.hand is not None:
            from joshua_runtime.emulators.sts3215_hand import run_hand

            hand = threading.Thread(target=run_hand, args=(emulator, args.hand, sys.stdout, should_stop), daemon=True)
            hand.start()
        while not should_stop():
            time.sleep(POLL_INTERVAL_S)
