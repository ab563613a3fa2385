"""The agent's local socket: `supervisor.py ctl --host NAME`, `ctl status --all-hosts` and the dashboard ask here.

A Unix stream socket beside the supervisor's control socket (`<name>.hosts.sock`), in the same private
directory (this user's, mode 0700), mode 0600; a client of another user than this one and root is refused
(SO_PEERCRED), like the control socket's. One JSON request per line, one JSON reply per line
(requests.py); at most MAX_CLIENTS at once.
"""

import asyncio
import json
import os
import socket
import stat
from pathlib import Path

from joshua_runtime.dashboard.control_client import PEER_CREDENTIALS
from joshua_runtime.errors import SettingsError
from joshua_runtime.hosts.requests import REQUEST_LIMIT_BYTES, refusal

MAX_CLIENTS = 64
PROBE_TIMEOUT_S = 1.0  # how long a socket already at the path may take to accept, before it counts as left over
READ_LIMIT_BYTES = REQUEST_LIMIT_BYTES + 2  # one request and its line end


def peer_uid(connection: socket.socket) -> int:
    return PEER_CREDENTIALS.unpack(connection.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, PEER_CREDENTIALS.size))[
        1
    ]


def check_directory(directory: Path) -> None:
    """Refuse a directory that is not this user's own with mode 0700 (another user could replace the socket)."""
    try:
        info = os.stat(directory, follow_symlinks=False)
    except OSError as exc:
        raise SettingsError(f"socket directory {directory}: {exc.strerror or exc}") from exc
    if not stat.S_ISDIR(info.st_mode) or info.st_uid != os.geteuid() or stat.S_IMODE(info.st_mode) & 0o077:
        raise SettingsError(f"socket directory {directory} must be a directory of uid {os.geteuid()} with mode 0700")


def claim(path: Path) -> None:
    """Remove a socket left at `path` by an agent that is gone; refuse one that is served, or any other file."""
    if not path.exists() and not path.is_symlink():
        return
    if not stat.S_ISSOCK(os.lstat(path).st_mode):
        raise SettingsError(f"{path} exists and is not a socket: not replacing it")
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
        probe.settimeout(PROBE_TIMEOUT_S)
        try:
            probe.connect(str(path))
        except OSError:
            path.unlink(missing_ok=True)
            return
    raise SettingsError(f"another agent serves {path}")


class Relay:
    """Serves the socket at `path`; `handle(line) -> dict` (a coroutine) answers each request line."""

    def __init__(self, path: Path, handle):
        self.path = path
        self.handle = handle
        self.server = None
        self.clients = 0

    async def start(self) -> None:
        check_directory(self.path.parent)
        claim(self.path)
        old_mask = os.umask(0o177)
        try:
            self.server = await asyncio.start_unix_server(self._serve, str(self.path), limit=READ_LIMIT_BYTES)
        except OSError as exc:
            raise SettingsError(f"cannot serve {self.path}: {exc.strerror or exc}") from exc
        finally:
            os.umask(old_mask)

    async def _serve(self, reader, writer) -> None:
        try:
            uid = peer_uid(writer.get_extra_info("socket"))
            if uid not in (os.geteuid(), 0):
                await self._send(writer, refusal("forbidden", f"uid {uid} may not use this socket"))
                return
            if self.clients >= MAX_CLIENTS:
                await self._send(writer, refusal("busy", f"too many clients ({MAX_CLIENTS}); try again later"))
                return
            self.clients += 1
            try:
                await self._requests(reader, writer)
            finally:
                self.clients -= 1
        except (OSError, asyncio.IncompleteReadError):
            pass
        finally:
            writer.close()

    async def _requests(self, reader, writer) -> None:
        while True:
            try:
                line = await reader.readline()
            except ValueError:  # longer than the limit: answered, then the connection is closed
                await self._send(writer, refusal("bad_request", f"request longer than {REQUEST_LIMIT_BYTES} bytes"))
                return
            if not line:
                return
            await self._send(writer, await self.handle(line.rstrip(b"\n")))

    @staticmethod
    async def _send(writer, reply: dict) -> None:
        writer.write(json.dumps(reply).encode() + b"\n")
        await writer.drain()

    def close(self) -> None:
        if self.server is not None:
            self.server.close()
        self.path.unlink(missing_ok=True)
