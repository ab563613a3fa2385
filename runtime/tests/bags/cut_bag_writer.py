"""Writes bags cut at given file sizes, as a full disk cuts them: `python cut_bag_writer.py ROOT SIZE...`.

For each SIZE, the process's file size limit (RLIMIT_FSIZE) is set to SIZE bytes, so the kernel writes
the part of a write below it and fails the rest, at any byte. A BagWriter under ROOT/SIZE then writes
MESSAGES messages, finishing a chunk after each, until a write fails; it is abandoned, as the recorder
abandons it. Each message's data is its number repeated, so a reader can tell which ones survived.
"""

import resource
import signal
import sys
from pathlib import Path

from joshua_runtime.bags import bag_writer

TOPIC, MESSAGE_TYPE = "/cut", "std_msgs/msg/String"
MESSAGES = 8
MESSAGE_BYTES = 200


def message(number: int) -> bytes:
    return bytes([number]) * MESSAGE_BYTES


def write_cut_bag(directory: Path, size: int) -> None:
    _, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (size, hard))
    writer = None
    try:
        writer = bag_writer.BagWriter(directory)
        writer.add_topic(TOPIC, MESSAGE_TYPE)
        for number in range(MESSAGES):
            writer.write(TOPIC, message(number), number + 1)
    except OSError:
        if writer is not None:
            writer.abandon()
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (hard, hard))


def main() -> None:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG instead
    bag_writer.CHUNK_FLUSH_PERIOD_S = 0  # a chunk per message: many record boundaries to cut between
    root = Path(sys.argv[1])
    for size in map(int, sys.argv[2:]):
        write_cut_bag(root / str(size), size)


if __name__ == "__main__":
    main()
