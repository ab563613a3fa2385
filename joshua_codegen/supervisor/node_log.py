"""Each node's output: passed on to the supervisor's own stderr and kept in `<log dir>/<node>.log`, rotated."""

import os
import sys

from joshua_codegen.supervisor.common import log

# A node's log file is rotated when it would grow past LOG_MAX_BYTES: <node>.log becomes <node>.log.1,
# .1 becomes .2, ... and the oldest of LOG_BACKUPS is dropped; at most (1 + LOG_BACKUPS) x 10 MiB a node.
LOG_MAX_BYTES = 10 * 1024 * 1024
LOG_BACKUPS = 3
LOG_READ_BYTES = 65536


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


class NodeLog:
    """The log file of one node; `feed` takes what the node's output pipe gave and hands complete lines on."""

    def __init__(self, directory: str, name: str):
        self.path = os.path.join(directory, f"{name}.log")
        self.partial = b""
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
            if self.partial:
                self.feed(b"\n")
            return False
        self.feed(data)
        return True

    def feed(self, data: bytes) -> None:
        try:
            sys.stderr.buffer.write(data)
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
        self.append(data)
        lines = (self.partial + data).split(b"\n")
        self.partial = lines.pop()
        for line in lines:
            text = line.decode(errors="replace")
            for listener in list(self.listeners):
                listener(text)

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
        """The last `count` lines, from the rotated files too when the current one holds fewer."""
        lines = []
        for path in [self.path] + [f"{self.path}.{index}" for index in range(1, LOG_BACKUPS + 1)]:
            if len(lines) >= count:
                break
            try:
                with open(path, "rb") as log_file:
                    older = log_file.read().decode(errors="replace").splitlines()
            except OSError:
                continue
            lines = older + lines
        return lines[-count:] if count > 0 else []
