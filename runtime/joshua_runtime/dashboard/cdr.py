"""JointState and Image messages read straight from their CDR bytes, as the dashboard takes them serialized.

rclpy's deserialize_message builds the whole ROS message in Python (every field through its checked
setter, the pixels copied into an array) for each message; the dashboard needs a few fields and a
view of the pixels. `decode` reads those into small tuples with the message's attribute names, so
frames.py draws them as it draws ROS messages. It reads the little-endian classic CDR encapsulation,
which ROS 2's middlewares use for these types on the machines a robot runs on; for any other it
answers None and the caller deserializes the message itself.
"""

import struct
from typing import NamedTuple

from joshua_core.message_types import JOINT_STATE

IMAGE = "sensor_msgs/msg/Image"
ENCAPSULATION_BYTES = 4  # the representation identifier and its options; alignment counts from after them
CDR_LE = b"\x00\x01"
_UINT32 = struct.Struct("<I")
_STAMP = struct.Struct("<iI")


class Stamp(NamedTuple):
    sec: int
    nanosec: int


class Header(NamedTuple):
    stamp: Stamp
    frame_id: str


class JointStateFields(NamedTuple):
    header: Header
    name: list[str]
    position: tuple[float, ...]
    velocity: tuple[float, ...]
    effort: tuple[float, ...]


class ImageFields(NamedTuple):
    header: Header
    height: int
    width: int
    encoding: str
    is_bigendian: int
    step: int
    data: memoryview  # a view of the serialized message: no copy of the pixels


class _Reader:
    """Reads CDR primitives in order, each aligned to its size from the end of the encapsulation header."""

    def __init__(self, data: bytes):
        self.data, self.view, self.offset = data, memoryview(data), ENCAPSULATION_BYTES

    def _align(self, size: int) -> None:
        self.offset += -(self.offset - ENCAPSULATION_BYTES) % size

    def uint32(self) -> int:
        self._align(4)
        (value,) = _UINT32.unpack_from(self.data, self.offset)
        self.offset += 4
        return value

    def uint8(self) -> int:
        value = self.data[self.offset]
        self.offset += 1
        return value

    def header(self) -> Header:
        self._align(4)
        stamp = Stamp(*_STAMP.unpack_from(self.data, self.offset))
        self.offset += 8
        return Header(stamp, self.string())

    def string(self) -> str:
        size = self.uint32()  # with the terminating NUL
        end = self.offset + size
        if size == 0 or end > len(self.data):
            raise ValueError(f"a string of {size} bytes at offset {self.offset} of {len(self.data)}")
        text = self.data[self.offset : end - 1].decode()
        self.offset = end
        return text

    def strings(self) -> list[str]:
        return [self.string() for _ in range(self.uint32())]

    def doubles(self) -> tuple[float, ...]:
        count = self.uint32()
        if count == 0:
            return ()
        self._align(8)
        values = struct.unpack_from(f"<{count}d", self.data, self.offset)
        self.offset += 8 * count
        return values

    def octets(self) -> memoryview:
        count = self.uint32()
        end = self.offset + count
        if end > len(self.data):
            raise ValueError(f"{count} bytes at offset {self.offset} of {len(self.data)}")
        view = self.view[self.offset : end]
        self.offset = end
        return view


def decode(message_type: str, data: bytes) -> JointStateFields | ImageFields | None:
    """The fields of a serialized JointState or Image; None for another type or encapsulation (deserialize
    it instead). A message cut short or inconsistent raises ValueError."""
    if data[:2] != CDR_LE or message_type not in (JOINT_STATE, IMAGE):
        return None
    reader = _Reader(data)
    try:
        if message_type == JOINT_STATE:
            return JointStateFields(
                reader.header(), reader.strings(), reader.doubles(), reader.doubles(), reader.doubles()
            )
        header, height, width, encoding = reader.header(), reader.uint32(), reader.uint32(), reader.string()
        return ImageFields(header, height, width, encoding, reader.uint8(), reader.uint32(), reader.octets())
    except (struct.error, IndexError, UnicodeDecodeError) as exc:
        raise ValueError(f"a {message_type} that is not valid CDR: {exc}") from exc
