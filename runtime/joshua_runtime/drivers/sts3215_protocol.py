"""Feetech SCS/STS packet encoding and decoding, shared by the STS3215 driver and its emulator.

Both directions use one layout: `FF FF ID LEN INST|ERR P1..Pn CHK` with LEN = n + 2 and
CHK = NOT(ID + LEN + INST|ERR + sum(P)) & 0xFF. `PacketParser` turns a byte stream into packets,
skipping garbage and resynchronising on the next `FF FF` after a bad frame.
"""

from dataclasses import dataclass

HEADER = b"\xff\xff"
BROADCAST_ID = 0xFE
MAX_SERVO_ID = 0xFD
MAX_LENGTH = 250  # largest LEN byte either side accepts
MIN_PACKET_BYTES = 6  # FF FF ID LEN INST CHK

INST_PING = 0x01
INST_READ = 0x02
INST_WRITE = 0x03
INST_REG_WRITE = 0x04
INST_ACTION = 0x05
INST_RECOVERY = 0x06
INST_RESTART = 0x08
INST_RESET = 0x0A
INST_CALIBRATE_POSITION = 0x0B
INST_SYNC_READ = 0x82
INST_SYNC_WRITE = 0x83

# Bits of the status ERR byte and of the Status register (65).
ERROR_VOLTAGE = 0x01
ERROR_ANGLE_SENSOR = 0x02
ERROR_OVERHEAT = 0x04
ERROR_OVERCURRENT = 0x08
ERROR_OVERLOAD = 0x20
ERROR_NAMES = {
    ERROR_VOLTAGE: "input voltage",
    ERROR_ANGLE_SENSOR: "angle sensor",
    ERROR_OVERHEAT: "overheat",
    ERROR_OVERCURRENT: "over-current",
    ERROR_OVERLOAD: "overload",
}


def checksum(body: bytes | bytearray) -> int:
    """Checksum of ID, LEN, INST/ERR and parameters."""
    return ~sum(body) & 0xFF


def encode(servo_id: int, code: int, params: bytes | bytearray = b"") -> bytes:
    """One packet: an instruction (code = INST) or a status (code = ERR)."""
    body = bytes([servo_id, len(params) + 2, code]) + bytes(params)
    return HEADER + body + bytes([checksum(body)])


def encode_sync_read(address: int, size: int, ids: list[int]) -> bytes:
    return encode(BROADCAST_ID, INST_SYNC_READ, bytes([address, size, *ids]))


def encode_sync_write(address: int, size: int, data: dict[int, bytes]) -> bytes:
    params = bytearray([address, size])
    for servo_id, value in data.items():
        params.append(servo_id)
        params += value
    return encode(BROADCAST_ID, INST_SYNC_WRITE, params)


def error_text(error: int) -> str:
    """Human-readable names of the bits set in a status ERR byte."""
    names = [name for bit, name in ERROR_NAMES.items() if error & bit]
    return ", ".join(names) or f"error 0x{error:02x}"


def to_sign_magnitude(value: int, sign_bit: int) -> int:
    """Encode a signed value: |value| with `sign_bit` set when negative (magnitude saturates)."""
    magnitude = min(abs(int(value)), (1 << sign_bit) - 1)
    return magnitude | (1 << sign_bit) if value < 0 else magnitude


def from_sign_magnitude(raw: int, sign_bit: int) -> int:
    magnitude = raw & ((1 << sign_bit) - 1)
    return -magnitude if raw & (1 << sign_bit) else magnitude


@dataclass(frozen=True)
class Packet:
    """A decoded packet. `code` is INST for instructions, ERR for status packets."""

    servo_id: int
    code: int
    params: bytes
    checksum_ok: bool = True

    @property
    def raw(self) -> bytes:
        return encode(self.servo_id, self.code, self.params)


class PacketParser:
    """Incremental decoder: feed() bytes, then pop() packets until it returns None.

    A frame with a bad checksum is returned once with checksum_ok False; only its first header byte is
    consumed, so a genuine packet hidden inside the bogus frame is still found.
    """

    def __init__(self):
        self._buffer = bytearray()
        self.discarded = 0  # bytes skipped because they framed no valid packet (noise, collisions)

    def feed(self, data: bytes) -> None:
        self._buffer += data

    def clear(self) -> None:
        self._buffer.clear()

    @property
    def pending(self) -> int:
        """Bytes held that do not yet form a packet."""
        return len(self._buffer)

    def drop_byte(self) -> None:
        """Give up on a stalled partial frame: skip its first byte and rescan."""
        del self._buffer[:1]
        self.discarded += 1

    def bytes_wanted(self) -> int:
        """How many more bytes would complete the frame at the head of the buffer (at least 1)."""
        buffer = self._buffer
        if len(buffer) >= 4 and buffer[:2] == HEADER and buffer[2] != 0xFF:
            return max(1, buffer[3] + 4 - len(buffer))
        return max(1, MIN_PACKET_BYTES - len(buffer))

    def pop(self) -> Packet | None:
        buffer = self._buffer
        while True:
            start = buffer.find(HEADER)
            if start < 0:
                # Keep a trailing FF: it may be the first half of the next header.
                keep = 1 if buffer[-1:] == b"\xff" else 0
                self.discarded += len(buffer) - keep
                del buffer[: len(buffer) - keep]
                return None
            self.discarded += start
            del buffer[:start]
            if len(buffer) < 4:
                return None
            if buffer[2] == 0xFF:  # FF FF FF: the header starts one byte later
                self.discarded += 1
                del buffer[:1]
                continue
            length = buffer[3]
            if length < 2 or length > MAX_LENGTH:
                self.discarded += 1
                del buffer[:1]
                continue
            total = length + 4
            if len(buffer) < total:
                return None
            body = bytes(buffer[2 : total - 1])
            ok = checksum(body) == buffer[total - 1]
            packet = Packet(servo_id=body[0], code=body[2], params=body[3:], checksum_ok=ok)
            self.discarded += 0 if ok else 1
            del buffer[: total if ok else 1]
            return packet
