"""Client of the supervisor's control socket: one JSON request per line, one JSON reply per line.

The protocol (requests `status`, `restart`/`stop`/`start` NODE, `logs` NODE) is the supervisor's;
every call opens its own connection, so a supervisor restarted meanwhile is simply found again.
"""

import asyncio
import json
import os
import socket
import struct
from pathlib import Path

# How long one request may take before the supervisor counts as unreachable (a restart waits for the old process).
REQUEST_TIMEOUT_S = 15.0
# The longest reply line accepted (a `logs` reply of many lines).
REPLY_LIMIT_BYTES = 8 * 1024 * 1024
NODE_ACTIONS = ("restart", "stop", "start")
# Set by a supervisor for its children when it serves its socket somewhere else than the default.
SOCKET_VARIABLE = "JOSHUA_CONTROL_SOCKET"
PEER_CREDENTIALS = struct.Struct("3i")  # SO_PEERCRED: pid, uid, gid


class ControlError(Exception):
    """The supervisor could not be reached or answered with an error (the message is one line)."""


def default_socket_path(robot: str) -> Path:
    """Where the supervisor serves its control socket: $JOSHUA_CONTROL_SOCKET, else its default path."""
    if os.environ.get(SOCKET_VARIABLE):
        return Path(os.environ[SOCKET_VARIABLE])
    runtime_dir = os.environ.get("XDG_RUNTIME_DIR")
    if runtime_dir:
        return Path(runtime_dir) / "joshua" / f"{robot}.sock"
    return Path(f"/tmp/joshua-{os.getuid()}") / f"{robot}.sock"


def check_server(connection, path: Path) -> None:
    """Refuse a socket served by another user than this one or root (someone who bound the path first)."""
    _, uid, _ = PEER_CREDENTIALS.unpack(
        connection.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, PEER_CREDENTIALS.size)
    )
    if uid not in (os.geteuid(), 0):
        raise ControlError(f"control socket {path} is served by uid {uid}, not by uid {os.geteuid()} or root")


class ControlClient:
    """Sends requests to the control socket at `path`."""

    def __init__(self, path: Path):
        self.path = path

    async def request(self, message: dict) -> dict:
        """Send one request; return its reply without "ok", or raise ControlError."""
        try:
            return await asyncio.wait_for(self._exchange(message), REQUEST_TIMEOUT_S)
        except TimeoutError as exc:
            raise ControlError(
                f"the supervisor did not answer {message['command']!r} within {REQUEST_TIMEOUT_S:g} s"
            ) from exc

    async def _exchange(self, message: dict) -> dict:
        try:
            reader, writer = await asyncio.open_unix_connection(str(self.path), limit=REPLY_LIMIT_BYTES)
        except OSError as exc:
            raise ControlError(f"control socket {self.path}: {exc.strerror or exc}") from exc
        try:
            check_server(writer.get_extra_info("socket"), self.path)
            writer.write(json.dumps(message).encode() + b"\n")
            await writer.drain()
            line = await reader.readline()
        except (OSError, ValueError) as exc:
            raise ControlError(f"control socket {self.path}: {exc}") from exc
        finally:
            writer.close()
        try:
            reply = json.loads(line)
        except ValueError as exc:
            raise ControlError(f"control socket {self.path} answered {line[:80]!r}, not a JSON line") from exc
        if not reply.get("ok"):
            raise ControlError(str(reply.get("error") or "the supervisor refused the request"))
        reply.pop("ok")
        return reply

    async def status(self) -> dict:
        return await self.request({"command": "status"})

    async def node_action(self, action: str, node: str) -> dict:
        if action not in NODE_ACTIONS:
            raise ControlError(f"unknown action {action!r} (use {', '.join(NODE_ACTIONS)})")
        return await self.request({"command": action, "node": node})

    async def logs(self, node: str, lines: int) -> list[str]:
        reply = await self.request({"command": "logs", "node": node, "lines": lines, "follow": False})
        return list(reply.get("lines") or [])
