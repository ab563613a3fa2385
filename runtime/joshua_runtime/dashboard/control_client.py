"""Client of the supervisor's control socket: one JSON request per line, one JSON reply per line.

The protocol (requests `status`, `restart`/`stop`/`start` NODE, `logs` NODE) is the supervisor's;
every call opens its own connection, so a supervisor restarted meanwhile is simply found again.
Every failure is a ControlError with a `kind` (one of ERROR_KINDS) that says what went wrong.
"""

import asyncio
import json
import os
import socket
import struct
from pathlib import Path

from joshua_runtime.dashboard.api_schema import enum, named

# How long one request may take before the supervisor counts as unreachable (a restart waits for the old process).
REQUEST_TIMEOUT_S = 15.0
# The longest reply line accepted (a `logs` reply of many lines).
REPLY_LIMIT_BYTES = 8 * 1024 * 1024
NODE_ACTIONS = enum("NodeAction")
# Set by a supervisor for its children when it serves its socket somewhere else than the default.
SOCKET_VARIABLE = "JOSHUA_CONTROL_SOCKET"
PEER_CREDENTIALS = struct.Struct("3i")  # SO_PEERCRED: pid, uid, gid


# What a ControlError can be (api.schema.json's ErrorKind). The supervisor's refusals, named in its error
# reply's `kind` (REFUSAL_KINDS of its control_request module; tests/test_dashboard_api.py holds them equal),
# come first; the rest are failures to get an answer at all.
CONFLICT = named("ErrorKind", "conflict")  # the node is already in the state asked for, or being stopped or restarted
NOT_FOUND = named("ErrorKind", "not_found")  # no node of that name
STOPPING = named("ErrorKind", "stopping")  # the robot is stopping
BAD_REQUEST = named("ErrorKind", "bad_request")  # a request the supervisor does not understand
FORBIDDEN = named("ErrorKind", "forbidden")  # the supervisor refuses this process's user
BUSY = named("ErrorKind", "busy")  # too many control clients are connected
INVALID_BUILD = named("ErrorKind", "invalid_build")  # a reload of a build that is not this robot's
PREFLIGHT = named("ErrorKind", "preflight")  # a node a reload would start cannot start
REFUSED = named("ErrorKind", "refused")  # a refusal of a kind this client does not know
UNREACHABLE = named("ErrorKind", "unreachable")  # no supervisor serves the socket
TIMEOUT = named("ErrorKind", "timeout")  # it did not answer in time
BROKEN = named("ErrorKind", "broken")  # it answered something that is not the control protocol
REFUSAL_KINDS = (CONFLICT, NOT_FOUND, STOPPING, BAD_REQUEST, FORBIDDEN, BUSY, INVALID_BUILD, PREFLIGHT)
ERROR_KINDS = (*REFUSAL_KINDS, REFUSED, UNREACHABLE, TIMEOUT, BROKEN)


class ControlError(Exception):
    """The supervisor could not be reached or answered with an error (the message is one line); `kind` is
    one of ERROR_KINDS."""

    def __init__(self, message: str, kind: str = REFUSED):
        super().__init__(message)
        self.kind = kind


def refusal_kind(reply: dict) -> str:
    """The kind of an error reply of the supervisor, as it names it (REFUSED for a kind unknown here); a host's
    agent also names UNREACHABLE, for a host that did not answer (joshua_runtime/hosts)."""
    named = reply.get("kind")
    return named if named in (*REFUSAL_KINDS, UNREACHABLE) else REFUSED


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
        raise ControlError(
            f"control socket {path} is served by uid {uid}, not by uid {os.geteuid()} or root", UNREACHABLE
        )


class ControlClient:
    """Sends requests to the control socket at `path`."""

    def __init__(self, path: Path):
        self.path = path

    async def request(self, message: dict) -> dict:
        """Send one request; return its reply without "ok", or raise ControlError."""
        reply = await self.reply(message)
        if not reply.get("ok"):
            error = " ".join(str(reply.get("error") or "the supervisor refused the request").split())
            raise ControlError(error, refusal_kind(reply))
        reply.pop("ok")
        return reply

    async def reply(self, message: dict, timeout_s: float | None = None) -> dict:
        """Send one request; its reply as the supervisor wrote it (`ok` true, or false with its `kind` and
        `error`: a host's agent passes refusals on as they are), or ControlError when none came in `timeout_s`
        (default REQUEST_TIMEOUT_S)."""
        timeout_s = REQUEST_TIMEOUT_S if timeout_s is None else timeout_s
        try:
            return await asyncio.wait_for(self._exchange(message), timeout_s)
        except asyncio.TimeoutError as exc:
            raise ControlError(
                f"the supervisor did not answer {message['command']!r} within {timeout_s:g} s", TIMEOUT
            ) from exc

    async def _exchange(self, message: dict) -> dict:
        try:
            reader, writer = await asyncio.open_unix_connection(str(self.path), limit=REPLY_LIMIT_BYTES)
        except OSError as exc:
            raise ControlError(f"control socket {self.path}: {exc.strerror or exc}", UNREACHABLE) from exc
        try:
            check_server(writer.get_extra_info("socket"), self.path)
            writer.write(json.dumps(message).encode() + b"\n")
            await writer.drain()
            line = await reader.readline()
        except OSError as exc:
            raise ControlError(f"control socket {self.path}: {exc.strerror or exc}", UNREACHABLE) from exc
        except ValueError as exc:  # a line longer than REPLY_LIMIT_BYTES
            raise ControlError(f"control socket {self.path}: {exc}", BROKEN) from exc
        finally:
            writer.close()
        if not line:
            raise ControlError(f"control socket {self.path}: the supervisor closed it without answering", UNREACHABLE)
        try:
            reply = json.loads(line)
        except ValueError:
            reply = None
        if not isinstance(reply, dict):
            raise ControlError(f"control socket {self.path} answered {line[:80]!r}, not a JSON object line", BROKEN)
        return reply

    async def status(self) -> dict:
        return await self.request({"command": "status"})

    async def node_action(self, action: str, node: str) -> dict:
        if action not in NODE_ACTIONS:
            raise ControlError(f"unknown action {action!r} (use {', '.join(NODE_ACTIONS)})", BAD_REQUEST)
        return await self.request({"command": action, "node": node})

    async def logs(self, node: str, lines: int) -> list[str]:
        reply = await self.request({"command": "logs", "node": node, "lines": lines, "follow": False})
        return list(reply.get("lines") or [])
