"""A node's output: lines longer than LINE_MAX_BYTES are cut and marked, in linear time and bounded memory."""

import os
import sys
import tracemalloc

import pytest

from joshua_codegen.supervisor.node_log import LINE_CUT_MARK, LINE_MAX_BYTES, LOG_READ_BYTES, NodeLog

CUT = LINE_CUT_MARK.decode()


@pytest.fixture
def node_log(tmp_path, monkeypatch):
    """A NodeLog writing to tmp_path/n.log, with the supervisor's stderr going to /dev/null."""
    devnull = open(os.devnull, "w")  # noqa: SIM115 (closed below)
    monkeypatch.setattr(sys, "stderr", devnull)
    log = NodeLog(str(tmp_path), "n")
    lines = []
    log.listeners.append(lines.append)
    yield log, lines
    devnull.close()


def feed_in_chunks(log: NodeLog, data: bytes, size: int) -> None:
    for start in range(0, len(data), size):
        log.feed(data[start : start + size])


def test_a_long_line_is_cut_into_marked_pieces_and_nothing_is_lost(node_log):
    log, lines = node_log
    long = bytes(ord("a") + i % 26 for i in range(2 * LINE_MAX_BYTES + 123))
    feed_in_chunks(log, long + b"\nshort\n", 1000)
    assert [len(line) for line in lines] == [LINE_MAX_BYTES + len(CUT)] * 2 + [123, 5]
    assert all(line.endswith(CUT) for line in lines[:2])
    assert "".join(line.removesuffix(CUT) for line in lines[:3]).encode() == long
    with open(log.path) as written:
        assert written.read() == "\n".join(lines) + "\n"


def test_a_line_of_the_cap_is_kept_whole_and_one_byte_more_is_cut_once(node_log):
    log, lines = node_log
    log.feed(b"x" * LINE_MAX_BYTES + b"\n")
    feed_in_chunks(log, b"y" * (LINE_MAX_BYTES + 1) + b"\n", 4096)
    assert lines == ["x" * LINE_MAX_BYTES, "y" * LINE_MAX_BYTES + CUT, "y"]


@pytest.mark.parametrize("chunk", [1000, LOG_READ_BYTES], ids=["cut-inside-a-read", "cut-at-a-reads-start"])
def test_a_cut_never_splits_a_utf8_character(node_log, chunk):
    log, lines = node_log
    text = "€" * (LINE_MAX_BYTES // 3 + 10)  # three bytes each: a cut at LINE_MAX_BYTES would split one
    feed_in_chunks(log, text.encode() + b"\n", chunk)
    assert "\ufffd" not in "".join(lines)
    assert "".join(line.removesuffix(CUT) for line in lines) == text
    assert len(lines) == 2 and abs(len(lines[0].removesuffix(CUT).encode()) - LINE_MAX_BYTES) < 3


def test_output_without_newlines_takes_bounded_memory(node_log):
    log, _ = node_log
    lengths = []
    log.listeners = [lambda line: lengths.append(len(line))]
    chunk = b"z" * LOG_READ_BYTES
    tracemalloc.start()
    try:
        for _ in range(256):  # 16 MiB without a newline
            log.feed(chunk)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 8 * LINE_MAX_BYTES, f"peak {peak} bytes"
    assert LOG_READ_BYTES <= LINE_MAX_BYTES  # what keeps every line but the running one within the cap
    assert lengths == [LINE_MAX_BYTES + len(CUT)] * (256 * LOG_READ_BYTES // LINE_MAX_BYTES - 1)


def test_end_of_output_ends_an_unfinished_line(node_log, tmp_path):
    log, lines = node_log
    read_end, write_end = log.open_pipe()
    os.write(write_end, b"no newline")
    os.close(write_end)
    while log.read(read_end):
        pass
    os.close(read_end)
    assert lines == ["no newline"]
    assert (tmp_path / "n.log").read_text() == "no newline\n"


def test_tail_reads_across_files_and_only_the_end_of_a_big_one(node_log, tmp_path):
    log, _ = node_log
    (tmp_path / "n.log.1").write_text("".join(f"old {n}\n" for n in range(5)))
    (tmp_path / "n.log").write_text("".join(f"new {n}\n" for n in range(3)))
    assert log.tail(5) == ["old 3", "old 4", "new 0", "new 1", "new 2"]
    assert log.tail(0) == []
    (tmp_path / "n.log").write_text("".join(f"line {n:07d}\n" for n in range(800000)))  # 10 MiB
    tracemalloc.start()
    try:
        tail = log.tail(3)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert tail == ["line 0799997", "line 0799998", "line 0799999"]
    assert peak < 8 * LINE_MAX_BYTES, f"peak {peak} bytes"
