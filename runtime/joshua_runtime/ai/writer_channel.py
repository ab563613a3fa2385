"""Messages between the recorder node and its dataset writer process: a JSON header, then raw numpy arrays.

One message is `(kind, data, arrays)`: `kind` a short word, `data` any JSON value, `arrays` a dict of
numpy arrays (a frame's action, state and images). On the pipe it is an 8-byte prefix (the lengths of
the header and of the array bytes), the UTF-8 JSON header `{"kind", "data", "arrays": [[name, dtype,
shape], ...]}` and the arrays' bytes one after the other. Nothing is pickled: both ends are this
program, but a pipe that carries only data can never run code.
"""

import json
import struct
import threading

import numpy as np

PREFIX = struct.Struct("<II")


def encode(kind: str, data=None, arrays: dict | None = None) -> bytes:
    arrays = arrays or {}
    layout = [[name, array.dtype.str, list(array.shape)] for name, array in arrays.items()]
    header = json.dumps({"kind": kind, "data": data, "arrays": layout}).encode()
    body = b"".join(np.ascontiguousarray(array).tobytes() for array in arrays.values())
    return PREFIX.pack(len(header), len(body)) + header + body


def read(stream) -> tuple[str, object, dict] | None:
    """The next message of a buffered binary stream; None at its end (the other side is gone)."""
    prefix = stream.read(PREFIX.size)
    if len(prefix) < PREFIX.size:
        return None
    header_size, body_size = PREFIX.unpack(prefix)
    header_bytes = stream.read(header_size)
    body = stream.read(body_size)
    if len(header_bytes) < header_size or len(body) < body_size:
        return None
    header = json.loads(header_bytes)
    arrays, offset = {}, 0
    for name, dtype, shape in header["arrays"]:
        kind = np.dtype(dtype)
        size = kind.itemsize * int(np.prod(shape, dtype=np.int64))
        arrays[name] = np.frombuffer(body, kind, count=size // kind.itemsize, offset=offset).reshape(shape).copy()
        offset += size
    return header["kind"], header["data"], arrays


class Sender:
    """Writes whole messages to a binary stream from any thread."""

    def __init__(self, stream):
        self.stream = stream
        self.lock = threading.Lock()

    def send(self, kind: str, data=None, arrays: dict | None = None) -> None:
        message = encode(kind, data, arrays)
        with self.lock:
            self.stream.write(message)
            self.stream.flush()
