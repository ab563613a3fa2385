"""A node's output: lines longer than LINE_MAX_BYTES are cut and marked, in linear time and bounded memory; each
line kept after its time; each run after its header, where `tail` begins unless asked for every run."""

import os
import re
import sys
import time
import tracemalloc

import pytest

from joshua_codegen.supervisor import node_log as node_log_module
from joshua_codegen.supervisor.node_log import LINE_CUT_MARK, LINE_MAX_BYTES, LOG_READ_BYTES, NodeLog

CUT = LINE_CUT_MARK.decode()
STAMP = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}[+-]\d\d:\d\d ")  # ISO 8601, offset, a space


def texts(lines: list[str]) -> list[str]:
    """The lines without their time, each checked to begin with one."""
    stripped = []
    for line in lines:
        stamp = STAMP.match(line)
        assert stamp, f"no time at the start of {line[:80]!r}"
        stripped.append(line[stamp.end() :])
    return stripped


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
    shown = texts(lines)
    assert [len(line) for line in shown] == [LINE_MAX_BYTES + len(CUT)] * 2 + [123, 5]
    assert all(line.endswith(CUT) for line in shown[:2])
    assert "".join(line.removesuffix(CUT) for line in shown[:3]).encode() == long
    with open(log.path) as written:
        assert written.read() == "\n".join(lines) + "\n"


def test_a_line_of_the_cap_is_kept_whole_and_one_byte_more_is_cut_once(node_log):
    log, lines = node_log
    log.feed(b"x" * LINE_MAX_BYTES + b"\n")
    feed_in_chunks(log, b"y" * (LINE_MAX_BYTES + 1) + b"\n", 4096)
    assert texts(lines) == ["x" * LINE_MAX_BYTES, "y" * LINE_MAX_BYTES + CUT, "y"]


@pytest.mark.parametrize("chunk", [1000, LOG_READ_BYTES], ids=["cut-inside-a-read", "cut-at-a-reads-start"])
def test_a_cut_never_splits_a_utf8_character(node_log, chunk):
    log, lines = node_log
    text = "€" * (LINE_MAX_BYTES // 3 + 10)  # three bytes each: a cut at LINE_MAX_BYTES would split one
    feed_in_chunks(log, text.encode() + b"\n", chunk)
    shown = texts(lines)
    assert "\ufffd" not in "".join(shown)
    assert "".join(line.removesuffix(CUT) for line in shown) == text
    assert len(shown) == 2 and abs(len(shown[0].removesuffix(CUT).encode()) - LINE_MAX_BYTES) < 3


def test_output_without_newlines_takes_bounded_memory(node_log):
    log, _ = node_log
    lengths = []
    log.listeners = [lambda line: lengths.append(len(line) - STAMP.match(line).end())]
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
    assert texts(lines) == ["no newline"]
    written = (tmp_path / "n.log").read_text()
    assert written.endswith("\n") and texts(written.splitlines()) == ["no newline"]


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


def test_each_line_in_the_file_and_to_listeners_follows_its_time_with_the_local_offset(tmp_path, monkeypatch):
    monkeypatch.setenv("TZ", "XYZ+3:30")  # 3 h 30 min west of UTC
    time.tzset()
    shown = tmp_path / "stderr"
    try:
        with open(shown, "w") as stderr:
            monkeypatch.setattr(sys, "stderr", stderr)
            log = NodeLog(str(tmp_path), "n")
            lines = []
            log.listeners.append(lines.append)
            log.feed(b"one\ntw")
            log.feed(b"o\n\nthree\n")
    finally:
        monkeypatch.undo()
        time.tzset()
    written = (tmp_path / "n.log").read_text().splitlines()
    assert written == lines and texts(lines) == ["one", "two", "", "three"]
    assert all(line[23:30] == "-03:30 " for line in lines)
    assert shown.read_text() == "one\ntwo\n\nthree\n"  # the supervisor's stderr gets the output as it came


def test_tail_reads_the_current_run_across_rotations_until_its_header_is_rotated_away(node_log, tmp_path, monkeypatch):
    log, _ = node_log
    monkeypatch.setattr(node_log_module, "LOG_MAX_BYTES", 200)
    (tmp_path / "n.log").write_text("old 0\nold 1\n")
    log.begin_run("-- run b --")
    for number in range(8):
        log.feed(f"new {number:02d}\n".encode())
    assert (tmp_path / "n.log.1").exists()  # the run's header is in a rotated file
    assert texts(log.tail(100)) == ["-- run b --"] + [f"new {number:02d}" for number in range(8)]
    assert texts(log.tail(3)) == ["new 05", "new 06", "new 07"]
    assert log.tail(100, all_runs=True)[:2] == ["old 0", "old 1"]
    assert texts(log.tail(100, all_runs=True)[2:]) == texts(log.tail(100))
    for number in range(8, 40):
        log.feed(f"new {number:02d}\n".encode())
    kept = texts(log.tail(100))
    assert "-- run b --" not in kept and kept[-1] == "new 39"
    assert kept == texts(log.tail(100, all_runs=True))  # every line kept is the current run's


def test_a_run_begins_on_a_line_of_its_own(node_log, tmp_path):
    log, _ = node_log
    (tmp_path / "n.log").write_text("cut short by a killed supervisor")
    log.begin_run("-- run c --")
    log.feed(b"first\n")
    written = (tmp_path / "n.log").read_text().splitlines()
    assert written[0] == "cut short by a killed supervisor" and texts(written[1:]) == ["-- run c --", "first"]
    assert texts(log.tail(100)) == ["-- run c --", "first"]
