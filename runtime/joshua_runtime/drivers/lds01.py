"""LDS-01 (HLS-LFCD2) lidar driver over pyserial: one PerceptionPacket "laser_scan" per turn.

Assembly follows the ROS driver (hls_lfcd_lds_driver): sync on `FA A0`, take that packet and the
59 that follow (2,520 bytes), and place reading n = 6k + j of packet k at scan index 359 - n.
A packet is used only when it passes the sanity check; the readings of a skipped packet stay 0
(0 means "no reading" in a LaserScan):

    byte 0 is 0xFA, byte 1 is 0xA0 + k for its position k in the turn (so the index byte is in
    0xA0-0xDB and in order), the speed field is non-zero, and, only with verify_checksum=True,
    bytes 40-41 equal the checksum of bytes 0-39 (see lds01_protocol; not confirmed on real
    devices, so off by default, as in the ROS driver).

A turn in which no packet passes is dropped. The scan's rpm is the mean speed of its good packets.

A read that gets no usable turn for `silent_timeout_s` before the device ever streamed
(SILENT_DEVICE_TIMEOUT_S: time for the motor to spin up) means it is not streaming; for
DEVICE_SILENCE_S once it has streamed, that it stopped (joshua_core.device_link). Both are a DeviceError.
"""

import time

import serial

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_core.schema import PerceptionPacket
from joshua_runtime.drivers import lds01_protocol as proto
from joshua_runtime.drivers.driver import Driver
from joshua_runtime.drivers.scan_geometry import fill_point_cloud
from joshua_runtime.errors import DeviceError

READ_POLL_S = 0.05  # longest single blocking read, so callers can stop promptly
SILENT_DEVICE_TIMEOUT_S = 2.0  # no complete turn for this long after opening: the device is not streaming
SCAN_KIND = "laser_scan"


class Lds01Driver(Driver):
    """Reads complete turns from an LDS-01 on `port`."""

    def __init__(
        self,
        port: str,
        baud_rate: int = proto.BAUD_RATE,
        frame_id: str = "laser",
        verify_checksum: bool = False,
        silent_timeout_s: float = SILENT_DEVICE_TIMEOUT_S,
    ):
        self.port = port
        self.baud_rate = baud_rate
        self.frame_id = frame_id
        self.verify_checksum = verify_checksum
        self.silent_timeout_s = silent_timeout_s
        self.packets_good = 0
        self.packets_skipped = 0
        self.turns_dropped = 0
        self._serial: serial.Serial | None = None
        self._buffer = bytearray()
        self._streaming = False  # a usable turn came since the port was opened

    def open(self) -> None:
        """Open the port, discard stale input and start the motor."""
        try:
            self._serial = serial.Serial(self.port, self.baud_rate, timeout=READ_POLL_S, write_timeout=READ_POLL_S)
            self._serial.reset_input_buffer()
            self._serial.write(proto.START_COMMAND)
        except (serial.SerialException, OSError, ValueError) as exc:
            self._serial = None
            raise DeviceError(f"cannot open LDS-01 lidar at {self.port}: {_reason(exc)}") from None
        self._buffer.clear()
        self._streaming = False

    def close(self) -> None:
        """Stop the motor and release the port (never raises)."""
        port, self._serial = self._serial, None
        if port is None:
            return
        try:
            port.write(proto.STOP_COMMAND)
            port.flush()
        except (serial.SerialException, OSError):
            pass
        finally:
            port.close()

    def read_scan(self, should_stop=lambda: False) -> PerceptionPacket | None:
        """The next complete turn; None when `should_stop()` became true first.

        Raises DeviceError when no usable turn arrives within `silent_timeout_s` before the first turn,
        or within DEVICE_SILENCE_S once the device has streamed.
        """
        if self._serial is None:
            raise DeviceError(f"LDS-01 lidar at {self.port} is not open")
        deadline = time.monotonic() + (DEVICE_SILENCE_S if self._streaming else self.silent_timeout_s)
        while not should_stop():
            turn, started = self._take_turn()
            if turn is not None:
                scan = self._assemble(turn, started)
                if scan is not None:
                    self._streaming = True
                    return scan
                self.turns_dropped += 1
                continue
            if time.monotonic() > deadline:
                raise self._silence()
            self._fill()
        return None

    def _silence(self) -> DeviceError:
        if self._streaming:
            return DeviceError(
                f"LDS-01 lidar at {self.port} stopped streaming: no usable scan for {DEVICE_SILENCE_S:g} s"
            )
        return DeviceError(
            f"LDS-01 lidar at {self.port} sent no usable scan within {self.silent_timeout_s:g} s "
            f"(silent device, wrong baud rate or not an LDS-01)"
        )

    def _fill(self) -> None:
        try:
            waiting = self._serial.in_waiting
            data = self._serial.read(max(1, waiting))
        except (serial.SerialException, OSError) as exc:
            raise DeviceError(f"LDS-01 lidar at {self.port} stopped answering: {_reason(exc)}") from None
        self._buffer += data

    def _take_turn(self) -> tuple[bytes | None, float]:
        """Cut the next 2,520 bytes that start with FA A0 out of the buffer, if they are all there."""
        start = self._buffer.find(proto.SYNC)
        if start < 0:
            # Keep a trailing 0xFA: it may be the first half of a sync split across reads.
            keep = 1 if self._buffer[-1:] == bytes((proto.START_BYTE,)) else 0
            del self._buffer[: len(self._buffer) - keep]
            return None, 0.0
        del self._buffer[:start]
        if len(self._buffer) < proto.TURN_BYTES:
            return None, 0.0
        turn = bytes(self._buffer[: proto.TURN_BYTES])
        del self._buffer[: proto.TURN_BYTES]
        return turn, time.time()

    def packet_is_sane(self, packet: bytes, k: int) -> bool:
        """The sanity check of the module docstring, for the packet at position k of a turn."""
        if packet[0] != proto.START_BYTE or packet[1] != proto.FIRST_INDEX + k:
            return False
        if proto.packet_speed(packet) == 0:
            return False
        return not self.verify_checksum or proto.packet_checksum(packet) == proto.checksum(packet)

    def _assemble(self, turn: bytes, received_at: float) -> PerceptionPacket | None:
        ranges = [0.0] * proto.READINGS_PER_TURN
        intensities = [0.0] * proto.READINGS_PER_TURN
        speeds = []
        for k in range(proto.PACKETS_PER_TURN):
            packet = turn[k * proto.PACKET_BYTES : (k + 1) * proto.PACKET_BYTES]
            if not self.packet_is_sane(packet, k):
                self.packets_skipped += 1
                continue
            self.packets_good += 1
            speeds.append(proto.packet_speed(packet))
            for j, (intensity, range_mm) in enumerate(proto.packet_readings(packet)):
                index = proto.scan_index(k, j)
                ranges[index] = range_mm / 1000.0
                intensities[index] = float(intensity)
        if not speeds:
            return None
        rpm = sum(speeds) / len(speeds) / proto.SPEED_SCALE
        # Stamp of the first reading: the turn ended when its last byte arrived.
        first_reading_ns = int((received_at - proto.time_increment_s(rpm) * proto.READINGS_PER_TURN) * 1e9)
        return scan_packet(ranges, intensities, rpm, self.frame_id, first_reading_ns)


def scan_packet(
    ranges: list[float], intensities: list[float], rpm: float, frame_id: str, stamp_ns: int
) -> PerceptionPacket:
    """A "laser_scan" PerceptionPacket of one LDS-01 turn (ranges in m, index = angle in degrees).

    `values` holds one number: the motor speed in rpm; point_cloud holds the valid readings as points.
    """
    time_increment = proto.time_increment_s(rpm)
    packet = PerceptionPacket(frame_id=frame_id)
    packet.timestamp.FromNanoseconds(stamp_ns)
    sensor = packet.sensor
    sensor.kind = SCAN_KIND
    sensor.ranges.extend(ranges)
    sensor.intensities.extend(intensities)
    sensor.values.append(rpm)
    sensor.angle_min = proto.ANGLE_MIN
    sensor.angle_max = proto.ANGLE_MAX
    sensor.angle_increment = proto.ANGLE_INCREMENT
    sensor.range_min = proto.RANGE_MIN_M
    sensor.range_max = proto.RANGE_MAX_M
    sensor.time_increment = time_increment
    sensor.scan_time = time_increment * proto.READINGS_PER_TURN
    fill_point_cloud(packet)
    return packet


def _reason(exc: Exception) -> str:
    """The useful part of a pyserial/OS error message, on one line."""
    text = str(exc).strip() or type(exc).__name__
    return " ".join(text.split())
