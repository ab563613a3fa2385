"""Pybricks hub facts (GATT service, commands, events) and the line protocol of the motor hub program.

Pybricks GATT: the command/event characteristic takes commands (first byte) written by the PC and
notifies events (first byte) from the hub; the capabilities characteristic reads `<HIIB`: largest
write in bytes, capability flags, largest program in bytes, number of program slots.

Line protocol between the PC and the hub program (hub/motor_hub.py), over the hub's stdin/stdout:
every line is `BODY*CC\n`, CC the XOR of BODY's bytes as two upper-case hex digits, BODY fields
separated by commas. A line whose checksum does not match, or that is not ASCII, is dropped, so
bytes lost or garbled on the link cost one line, never a misread value.
    PC -> hub  `V,<seq>,<left deg/s>,<right deg/s>`   set both wheel speeds, answered by `K,<seq>`
    PC -> hub  `S,<seq>`                              stop both wheels, answered by `K,<seq>`
    hub -> PC  `R`                                    the program runs and waits for commands
    hub -> PC  `K,<seq>`                              command <seq> applied
    hub -> PC  `A,<hub ms>,<left deg>,<right deg>`    wheel angles, REPORT_PERIOD_MS apart
The program stops both wheels on its own when no command came for HUB_WATCHDOG_MS.
"""

import struct
from dataclasses import dataclass

SERVICE_UUID = "c5f50001-8280-46da-89f4-6d8051e4aeef"
COMMAND_EVENT_UUID = "c5f50002-8280-46da-89f4-6d8051e4aeef"
CAPABILITIES_UUID = "c5f50003-8280-46da-89f4-6d8051e4aeef"
DEFAULT_HUB_NAME = "Pybricks Hub"

# Commands (first byte written to the command/event characteristic).
CMD_STOP_PROGRAM = 0
CMD_START_PROGRAM = 1
CMD_WRITE_PROGRAM_META = 3
CMD_WRITE_RAM = 4
CMD_WRITE_STDIN = 6
# Events (first byte of a notification).
EVENT_STATUS = 0
EVENT_STDOUT = 1
STATUS_PROGRAM_RUNNING = 1 << 6
CAPABILITIES_FORMAT = "<HIIB"
# Bytes of a write-RAM command before its payload: command byte and 32-bit offset.
WRITE_RAM_HEADER = 5

REPORT_PERIOD_MS = 20
HUB_WATCHDOG_MS = 1000
MAX_LINE = 96
# The first byte of every line either side sends.
LINE_STARTS = (b"A", b"K", b"R", b"S", b"V")


@dataclass(frozen=True)
class Capabilities:
    max_write: int
    flags: int
    max_program: int
    slots: int


def unpack_capabilities(data: bytes) -> Capabilities:
    """The capabilities characteristic's value; ValueError when it is not 11 bytes."""
    if len(data) != struct.calcsize(CAPABILITIES_FORMAT):
        raise ValueError(f"hub capabilities are {len(data)} bytes, expected 11")
    return Capabilities(*struct.unpack(CAPABILITIES_FORMAT, data))


def pack_capabilities(caps: Capabilities) -> bytes:
    return struct.pack(CAPABILITIES_FORMAT, caps.max_write, caps.flags, caps.max_program, caps.slots)


def status_event(flags: int, program_id: int = 0) -> bytes:
    return struct.pack("<BIB", EVENT_STATUS, flags, program_id)


def status_flags(event: bytes) -> int:
    """The flags of a status-report event."""
    return struct.unpack_from("<I", event, 1)[0]


def checksum(body: bytes) -> int:
    value = 0
    for byte in body:
        value ^= byte
    return value


def encode_line(*fields) -> bytes:
    """One framed line from its fields (numbers written with at most 3 decimals)."""
    body = ",".join(f"{f:.3f}".rstrip("0").rstrip(".") if isinstance(f, float) else str(f) for f in fields)
    data = body.encode("ascii")
    return data + b"*%02X\n" % checksum(data)


def decode_line(line: bytes) -> list[str] | None:
    """The fields of one framed line (without its newline); None when its framing or checksum is wrong."""
    line = line.rstrip(b"\r")
    star = line.rfind(b"*")
    if star < 1 or len(line) - star != 3:
        return None
    body = line[:star]
    try:
        if int(line[star + 1 :], 16) != checksum(body):
            return None
        return body.decode("ascii").split(",")
    except ValueError:
        return None


def resynchronised(line: bytes) -> list[str] | None:
    """The fields of a line, or of its longest tail that is a valid line (garbage glued to its front)."""
    for start in range(len(line) - 3):
        if start == 0 or line[start : start + 1] in LINE_STARTS:
            fields = decode_line(line[start:])
            if fields is not None:
                return fields
    return None


class LineAssembler:
    """Turns stdout chunks (lines split anywhere, garbage in between) into the fields of valid lines."""

    def __init__(self):
        self.buffer = b""
        self.rejected = 0

    def feed(self, chunk: bytes) -> list[list[str]]:
        self.buffer += chunk
        *lines, self.buffer = self.buffer.split(b"\n")
        if len(self.buffer) > MAX_LINE:  # no newline for too long: garbage
            self.buffer, self.rejected = b"", self.rejected + 1
        found = []
        for line in lines:
            fields = resynchronised(line)
            if fields is None:
                self.rejected += 1 if line.strip() else 0
            else:
                found.append(fields)
        return found


@dataclass(frozen=True)
class AngleReport:
    hub_ms: int
    left_deg: float
    right_deg: float


def parse_angles(fields: list[str]) -> AngleReport | None:
    """An `A` line's report; None when its fields are not numbers."""
    if len(fields) != 4 or fields[0] != "A":
        return None
    try:
        return AngleReport(int(fields[1]), float(fields[2]), float(fields[3]))
    except ValueError:
        return None
