"""LDS-01 (HLS-LFCD2) wire format: packet layout, scan geometry and the packet checksum.

One turn is 60 packets of 42 bytes, sent in order. Packet k (0..59):

    byte 0       0xFA
    byte 1       0xA0 + k
    bytes 2-3    motor speed, u16 little-endian, rpm x 10
    bytes 4-39   6 readings of 6 bytes: intensity u16 LE, range u16 LE in mm, 2 reserved
    bytes 40-41  checksum, u16 LE

Reading n = 6k + j of a turn belongs at scan index 359 - n (angle 359 - n degrees).

The checksum has no official definition (the ROS driver ignores it). The one used here is the
community description of the Neato XV-11 packet checksum applied to the 20 little-endian words of
bytes 0-39: acc = (acc << 1) + word for each word, then ((acc & 0x7FFF) + (acc >> 15)) & 0x7FFF.
The emulator writes it; the driver checks it only when asked (`verify_checksum=True`), because it
is not confirmed on real devices.
"""

import math
import struct

from joshua_core.devices import LDS01_BAUD_RATE

START_BYTE = 0xFA
FIRST_INDEX = 0xA0
SYNC = bytes((START_BYTE, FIRST_INDEX))
PACKET_BYTES = 42
PACKETS_PER_TURN = 60
READINGS_PER_PACKET = 6
READING_BYTES = 6
READINGS_OFFSET = 4
CHECKSUM_OFFSET = 40
READINGS_PER_TURN = PACKETS_PER_TURN * READINGS_PER_PACKET
TURN_BYTES = PACKETS_PER_TURN * PACKET_BYTES

BAUD_RATE = LDS01_BAUD_RATE
NOMINAL_RPM = 300.0
SPEED_SCALE = 10  # speed field = rpm x 10
START_COMMAND = b"b"
STOP_COMMAND = b"e"

RANGE_MIN_M = 0.12
RANGE_MAX_M = 3.5
ANGLE_MIN = 0.0
ANGLE_INCREMENT = 2.0 * math.pi / READINGS_PER_TURN
ANGLE_MAX = 2.0 * math.pi - ANGLE_INCREMENT

_HEADER = struct.Struct("<BBH")
_READING = struct.Struct("<HHH")
_WORDS = struct.Struct("<20H")
_CHECKSUM = struct.Struct("<H")


def checksum(first_40_bytes: bytes) -> int:
    """The packet checksum over bytes 0-39 (see the module docstring)."""
    acc = 0
    for word in _WORDS.unpack(first_40_bytes[:CHECKSUM_OFFSET]):
        acc = (acc << 1) + word
    return ((acc & 0x7FFF) + (acc >> 15)) & 0x7FFF


def encode_packet(index: int, speed: int, readings: list[tuple[int, int]]) -> bytes:
    """One packet: `readings` are 6 (intensity, range_mm) pairs; the checksum is appended."""
    body = bytearray(_HEADER.pack(START_BYTE, FIRST_INDEX + index, speed))
    for intensity, range_mm in readings:
        body += _READING.pack(intensity, range_mm, 0)
    return bytes(body) + _CHECKSUM.pack(checksum(body))


def packet_speed(packet: bytes) -> int:
    return _HEADER.unpack_from(packet)[2]


def packet_checksum(packet: bytes) -> int:
    return _CHECKSUM.unpack_from(packet, CHECKSUM_OFFSET)[0]


def packet_readings(packet: bytes) -> list[tuple[int, int]]:
    """The 6 (intensity, range_mm) pairs of a packet."""
    return [_READING.unpack_from(packet, READINGS_OFFSET + j * READING_BYTES)[:2] for j in range(READINGS_PER_PACKET)]


def scan_index(packet_index: int, reading: int) -> int:
    """Scan index (degrees) of reading `reading` (0..5) of packet `packet_index` (0..59)."""
    return READINGS_PER_TURN - 1 - (packet_index * READINGS_PER_PACKET + reading)


def time_increment_s(rpm: float) -> float:
    """Time between two readings at `rpm`: one turn is 360 readings."""
    return 1.0 / (rpm * 6.0)
