"""Poller: descriptors above 1023 (out of select()'s reach) work, and a number closed while registered
and handed out again is watched anew."""

import os
import resource

import pytest

from joshua_codegen.supervisor.poller import Poller

HIGH_FD = 1500


def test_a_descriptor_above_1023_is_watched_for_reading_and_writing():
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, HIGH_FD + 1), hard))
    read_end, write_end = os.pipe()
    high = os.dup2(read_end, HIGH_FD)
    poller = Poller()
    seen = []
    try:
        poller.readers[high] = lambda: seen.append(("read", os.read(high, 10)))
        poller.writers[write_end] = lambda: seen.append(("write", None))
        poller.wait(0)
        assert seen == [("write", None)]
        del poller.writers[write_end]
        os.write(write_end, b"x")
        poller.wait(1.0)
        assert seen[1:] == [("read", b"x")]
    finally:
        poller.close()
        for fd in (read_end, write_end, high):
            os.close(fd)
        resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))


@pytest.mark.parametrize("left", [True, False], ids=["left the poller after close", "never left"])
def test_a_number_closed_while_registered_is_watched_anew_when_it_comes_back(left):
    poller = Poller()
    first_read, first_write = os.pipe()
    poller.readers[first_read] = lambda: None
    os.close(first_read)  # before leaving the poller
    if left:
        del poller.readers[first_read]
    second_read, second_write = os.pipe()
    seen = []
    try:
        assert second_read == first_read  # the lowest free number comes back
        poller.readers[second_read] = lambda: seen.append(os.read(second_read, 10))
        os.write(second_write, b"y")
        poller.wait(1.0)
        assert seen == [b"y"]
    finally:
        poller.close()
        for fd in (first_write, second_read, second_write):
            os.close(fd)
