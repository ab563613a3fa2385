"""A bag cut by a failed write (a full disk) reads to its last whole chunk and then ends, wherever the cut fell.

The kernel writes the part of a write that fits and fails the rest, so a file can end half way into a
chunk or its message index; mcap's streaming reader then fails on that record with an error of its
own instead of reaching the end. The writer must leave the file at its last whole record. The cut is
made at every few bytes by a file size limit in a child process (cut_bag_writer.py).
"""

import subprocess
import sys
from pathlib import Path

import pytest
from cut_bag_writer import MESSAGES, message
from mcap.exceptions import EndOfFile
from mcap.reader import NonSeekingReader

pytestmark = pytest.mark.process

WRITER = Path(__file__).with_name("cut_bag_writer.py")
FIRST_CUT, LAST_CUT, CUT_STEP = 60, 1400, 7  # from just past the header to past the whole file (1.2 kB)


def streamed(path: Path) -> list[bytes]:
    """The data of every message read before the file ends; any error but the end fails the test."""
    found = []
    with open(path, "rb") as stream:
        try:
            for _, _, record in NonSeekingReader(stream, validate_crcs=True).iter_messages(log_time_order=False):
                found.append(record.data)
        except EndOfFile:
            pass
    return found


def test_a_bag_cut_at_any_byte_reads_to_its_last_whole_chunk(tmp_path):
    sizes = range(FIRST_CUT, LAST_CUT, CUT_STEP)
    subprocess.run([sys.executable, WRITER, tmp_path, *map(str, sizes)], check=True, timeout=120)
    survivors = set()
    for size in sizes:
        if not (tmp_path / str(size)).exists():  # too small for the bag's start: nothing of it is left
            survivors.add(0)
            continue
        [path] = (tmp_path / str(size)).glob("*.mcap")
        assert path.stat().st_size <= size
        found = streamed(path)
        assert found == [message(number) for number in range(len(found))], size
        survivors.add(len(found))
    assert survivors == set(range(MESSAGES + 1))  # the cuts fell before, between and after every message
