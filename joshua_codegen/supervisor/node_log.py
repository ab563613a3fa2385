"""Each node's output: overlong lines cut, passed on to stderr, kept in `<log dir>/<node>.log` with times and runs."""

import os
import sys
import time

from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.run_mark import log_time

# A node's log file is rotated when it would grow past LOG_MAX_BYTES: <node>.log becomes <node>.log.1,
# .1 becomes .2, ... and the oldest of LOG_BACKUPS is dropped; at most (1 + LOG_BACKUPS) x 10 MiB a node.
LOG_MAX_BYTES = 10 * 1024 * 1024
LOG_BACKUPS = 3
LOG_READ_BYTES = 65536  # at most this much is read from a node's pipe at once
# A line longer than LINE_MAX_BYTES is cut into lines of that many bytes (a few more or fewer rather than
# inside a UTF-8 character), each but the last ending in LINE_CUT_MARK, as journald's LineMax cuts lines
# (marking them _LINE_BREAK=line-max). Since a read is no longer than a line may be, only the line running
# on from earlier reads can grow past the cap: each read costs time in proportion to its length, and a
# node's unfinished line takes at most LINE_MAX_BYTES of memory.
LINE_MAX_BYTES = 65536
LINE_CUT_MARK = f" [line cut at {LINE_MAX_BYTES} bytes, continued below]".encode()
UTF8_CONTINUATION = range(0x80, 0xC0)  # the bytes that continue a UTF-8 character, never start one
TAIL_BLOCK_BYTES = 65536  # log files are read backwards in blocks of this size to find their last lines
LOG_TAIL_BYTES = 1024 * 1024  # most output one `logs` request reads (its reply must fit a client's buffer)


def default_log_dir(robot: str) -> str:
    """$XDG_STATE_HOME/joshua/<robot>/logs, else ~/.local/state/joshua/<robot>/logs."""
    state = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return os.path.join(state, "joshua", robot, "logs")


def open_node_logs(directory: str | None, names: list[str]) -> dict:
    """A NodeLog per node name in `directory` (created 0700); none when there is no directory."""
    if not directory:
        return {}
    try:
        os.makedirs(directory, mode=0o700, exist_ok=True)
    except OSError as exc:
        log("supervisor", f"warning: no node logs in {directory}: {exc}")
        return {}
    return {name: NodeLog(directory, name) for name in names}


def character_start(data: bytes, cut: int, start: int, end: int) -> int:
    """`cut` moved to the start of a UTF-8 character: back (by up to three bytes, staying after `start`)
    where it can, else forward (by up to three, staying before `end`); unmoved in data that is not UTF-8."""
    if data[cut] not in UTF8_CONTINUATION:
        return cut
    for back in range(cut - 1, max(start, cut - 4), -1):
        if data[back] not in UTF8_CONTINUATION:
            return back
    for forward in range(cut + 1, min(end, cut + 4)):
        if data[forward] not in UTF8_CONTINUATION:
            return forward
    return cut


class NodeLog:
    """The output of one node: `feed` takes what its pipe gave, cuts overlong lines, and passes the result
    to the supervisor's stderr as it is, and with each line after the time it was read (`log_time` and a
    space) to the log file and the listeners (which get complete lines). `begin_run` writes a run's header
    line into the file; `tail` reads the current run's lines, or every run's."""

    def __init__(self, directory: str, name: str):
        self.path = os.path.join(directory, f"{name}.log")
        self.line_length = 0  # bytes of the unfinished line passed on so far
        self.partial = bytearray()  # the unfinished line with its time, for the listeners (at most LINE_MAX_BYTES more)
        self.listeners = []  # callables taking one decoded line, e.g. `ctl logs -f` clients
        # Where the current run's header is: [rotations of the file since it was written, its offset in the file
        # it was written to]; None before begin_run (every line then counts as the current run's).
        self.run_start = None

    def begin_run(self, header: str) -> None:
        """Start a run: its `header` on a line of its own (an unfinished line a killed supervisor left is ended
        first), after which `tail` reads by default."""
        data = f"{log_time(time.time())} {header}\n".encode()
        if not ends_a_line(self.path):
            data = b"\n" + data
        offset = self.append(data)
        if offset is not None:
            self.run_start = [0, offset + (data[0] == ord("\n"))]

    def open_pipe(self):
        """(read end, write end) of a new pipe for one launch; the read end is non-blocking."""
        read_end, write_end = os.pipe()
        os.set_blocking(read_end, False)
        return read_end, write_end

    def read(self, fd: int) -> bool:
        """Read what is available on the node's pipe; False at end of file (every writer gone)."""
        try:
            data = os.read(fd, LOG_READ_BYTES)
        except BlockingIOError:
            return True
        except OSError:
            data = b""
        if not data:
            if self.line_length:
                self.feed(b"\n")
            return False
        self.feed(data)
        return True

    def feed(self, data: bytes) -> None:
        at_line_start = self.line_length == 0
        data = self.cut_long_lines(data)
        try:
            sys.stderr.buffer.write(data)
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
        data = stamp_lines(data, f"{log_time(time.time())} ".encode(), at_line_start)
        self.append(data)
        end = data.rfind(b"\n")
        if end < 0:
            self.partial += data
            return
        if self.listeners:
            lines = (bytes(self.partial) + data[:end]).split(b"\n")
            for line in lines:
                text = line.decode(errors="replace")
                for listener in list(self.listeners):
                    listener(text)
        self.partial = bytearray(data[end + 1 :])

    def cut_long_lines(self, data: bytes) -> bytes:
        """`data` with LINE_CUT_MARK and a newline put in wherever the line it continues would grow past
        LINE_MAX_BYTES; every later line in `data` is shorter than a read, so within the cap."""
        first = data.find(b"\n")
        head = len(data) if first < 0 else first  # where the line running on ends in `data`
        pieces, start = [], 0
        while head - start > LINE_MAX_BYTES - self.line_length:
            cut = character_start(data, start + LINE_MAX_BYTES - self.line_length, start, head)
            pieces += (data[start:cut], LINE_CUT_MARK, b"\n")
            start, self.line_length = cut, 0
        self.line_length = self.line_length + len(data) - start if first < 0 else len(data) - data.rfind(b"\n") - 1
        if not pieces:
            return data
        pieces.append(data[start:])
        return b"".join(pieces)

    def append(self, data: bytes) -> int | None:
        """Write `data` at the end of the log file, rotated first when it would grow past LOG_MAX_BYTES: the
        offset it was written at, None when it could not be written."""
        try:
            size = os.path.getsize(self.path) if os.path.exists(self.path) else 0
            if size and size + len(data) > LOG_MAX_BYTES:
                self.rotate()
                size = 0
            with open(self.path, "ab") as log_file:
                log_file.write(data)
            return size
        except OSError:
            return None  # a full or read-only disk must not stop the robot; stderr still has the output

    def rotate(self) -> None:
        for index in range(LOG_BACKUPS - 1, 0, -1):
            older = f"{self.path}.{index}"
            if os.path.exists(older):
                os.replace(older, f"{self.path}.{index + 1}")
        os.replace(self.path, f"{self.path}.1")
        if self.run_start is not None:
            self.run_start[0] += 1

    def tail(self, count: int, all_runs: bool = False) -> list[str]:
        """The last `count` lines of the current run (from its header on), or of every run kept when `all_runs`;
        from the rotated files too when the current one holds fewer; from the last LOG_TAIL_BYTES of output at
        most (fewer lines when they are long)."""
        paths = [self.path] + [f"{self.path}.{index}" for index in range(1, LOG_BACKUPS + 1)]
        starts = [0] * len(paths)  # where each file's lines of interest begin
        if not all_runs and self.run_start is not None and self.run_start[0] < len(paths):
            rotations, offset = self.run_start
            paths, starts = paths[: rotations + 1], [*starts[:rotations], offset]
        lines: list[bytes] = []
        budget = LOG_TAIL_BYTES
        for path, start in zip(paths, starts):
            if len(lines) >= count or budget <= 0:
                break
            found, read = last_lines(path, count - len(lines), budget, start)
            lines = found + lines
            budget -= read
        return [line.decode(errors="replace") for line in lines[-count:]] if count > 0 else []


def stamp_lines(data: bytes, stamp: bytes, at_line_start: bool) -> bytes:
    """`data` with `stamp` before every line that begins in it (its first only when it is `at_line_start`)."""
    body = data[:-1].replace(b"\n", b"\n" + stamp) + data[-1:]
    return stamp + body if at_line_start else body


def ends_a_line(path: str) -> bool:
    """Whether the file at `path` is empty, absent, unreadable or ends with a newline."""
    try:
        with open(path, "rb") as log_file:
            if log_file.seek(0, os.SEEK_END) == 0:
                return True
            log_file.seek(-1, os.SEEK_END)
            return log_file.read(1) == b"\n"
    except OSError:
        return True


def last_lines(path: str, count: int, budget: int, start: int = 0) -> tuple[list[bytes], int]:
    """The last `count` lines of the file at `path` after offset `start` (where a line begins; the whole file
    when it is shorter, since something else truncated it) within its last `budget` bytes (fewer when it holds
    fewer; none when it is absent), read backwards in blocks of TAIL_BLOCK_BYTES; and how many bytes were read."""
    try:
        with open(path, "rb") as log_file:
            position = log_file.seek(0, os.SEEK_END)
            start = start if start <= position else 0
            blocks: list[bytes] = []
            newlines = read = 0
            while position > start and newlines <= count and read < budget:
                size = min(TAIL_BLOCK_BYTES, position - start, budget - read)
                position -= size
                log_file.seek(position)
                blocks.insert(0, log_file.read(size))
                newlines += blocks[0].count(b"\n")
                read += size
    except OSError:
        return [], 0
    lines = b"".join(blocks).splitlines()
    if position > start:
        lines = lines[1:]  # the first may have begun in a block not read
    return (lines[-count:] if count > 0 else []), read
