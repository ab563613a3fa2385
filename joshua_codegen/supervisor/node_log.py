"""Each node's output: overlong lines cut, passed on to the supervisor's stderr and kept in `<log dir>/<node>.log`."""

import os
import sys

from joshua_codegen.supervisor.common import log

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
    to the supervisor's stderr, the log file and the listeners (which get complete lines)."""

    def __init__(self, directory: str, name: str):
        self.path = os.path.join(directory, f"{name}.log")
        self.line_length = 0  # bytes of the unfinished line passed on so far
        self.partial = bytearray()  # the unfinished line, for the listeners (at most LINE_MAX_BYTES)
        self.listeners = []  # callables taking one decoded line, e.g. `ctl logs -f` clients

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
        data = self.cut_long_lines(data)
        try:
            sys.stderr.buffer.write(data)
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
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

    def append(self, data: bytes) -> None:
        try:
            if os.path.exists(self.path) and os.path.getsize(self.path) + len(data) > LOG_MAX_BYTES:
                self.rotate()
            with open(self.path, "ab") as log_file:
                log_file.write(data)
        except OSError:
            pass  # a full or read-only disk must not stop the robot; stderr still has the output

    def rotate(self) -> None:
        for index in range(LOG_BACKUPS - 1, 0, -1):
            older = f"{self.path}.{index}"
            if os.path.exists(older):
                os.replace(older, f"{self.path}.{index + 1}")
        os.replace(self.path, f"{self.path}.1")

    def tail(self, count: int) -> list[str]:
        """The last `count` lines, from the rotated files too when the current one holds fewer; from the last
        LOG_TAIL_BYTES of output at most (fewer lines when they are long)."""
        lines: list[bytes] = []
        budget = LOG_TAIL_BYTES
        for path in [self.path] + [f"{self.path}.{index}" for index in range(1, LOG_BACKUPS + 1)]:
            if len(lines) >= count or budget <= 0:
                break
            found, read = last_lines(path, count - len(lines), budget)
            lines = found + lines
            budget -= read
        return [line.decode(errors="replace") for line in lines[-count:]] if count > 0 else []


def last_lines(path: str, count: int, budget: int) -> tuple[list[bytes], int]:
    """The last `count` lines of the file at `path` within its last `budget` bytes (fewer when it holds fewer;
    none when it is absent), read backwards in blocks of TAIL_BLOCK_BYTES; and how many bytes were read."""
    try:
        with open(path, "rb") as log_file:
            position = log_file.seek(0, os.SEEK_END)
            blocks: list[bytes] = []
            newlines = read = 0
            while position > 0 and newlines <= count and read < budget:
                size = min(TAIL_BLOCK_BYTES, position, budget - read)
                position -= size
                log_file.seek(position)
                blocks.insert(0, log_file.read(size))
                newlines += blocks[0].count(b"\n")
                read += size
    except OSError:
        return [], 0
    lines = b"".join(blocks).splitlines()
    if position > 0:
        lines = lines[1:]  # the first may have begun in a block not read
    return (lines[-count:] if count > 0 else []), read
