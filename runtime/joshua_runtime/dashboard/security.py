"""Who may use the API: the owner's bearer token, same-origin writes, and only Host names on an allow-list.

The robot's dashboard always requires its token (see joshua_core.dashboard_token); the fleet view
requires one beyond loopback only (`required_token`).
"""

import hmac
import ipaddress
import secrets
import socket

from starlette.responses import JSONResponse

from joshua_core.dashboard import LOOPBACK_NAMES, WILDCARD_BINDS, is_loopback

TOKEN_BYTES = 24
MAX_HOST_SHOWN_CHARS = 100  # of a refused Host header, in the error reply
LOOPBACK_ADDRESSES = ("127.0.0.1", "::1")  # what `localhost` stands for


def required_token(bind: str, given: str | None) -> tuple[str | None, bool]:
    """The fleet view's rule: (token the API requires or None, whether it was generated here and must
    be shown once)."""
    if given:
        return given, False
    if is_loopback(bind):
        return None, False
    return secrets.token_urlsafe(TOKEN_BYTES), True


class ApiGuard:
    """ASGI middleware: every /api/ request needs `Authorization: Bearer TOKEN` when a token is set (401
    otherwise); a POST from a page of another origin is refused (403), so no other site drives the robot."""

    def __init__(self, app, token: str | None):
        self.app = app
        self.expected = f"Bearer {token}".encode() if token else None

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or not scope["path"].startswith("/api/"):
            return await self.app(scope, receive, send)
        headers = dict(scope["headers"])
        if self.expected is not None and not hmac.compare_digest(headers.get(b"authorization", b""), self.expected):
            response = JSONResponse(
                {"error": "missing or wrong bearer token"}, status_code=401, headers={"WWW-Authenticate": "Bearer"}
            )
            return await response(scope, receive, send)
        if scope["method"] != "GET" and not _same_origin(headers):
            return await JSONResponse({"error": "cross-origin request refused"}, status_code=403)(scope, receive, send)
        return await self.app(scope, receive, send)


def _same_origin(headers: dict) -> bool:
    origin = headers.get(b"origin")
    if origin is None:
        return True  # not sent by a browser page (curl, the fleet, tests)
    return origin.split(b"://", 1)[-1] == headers.get(b"host", b"")


class HostAllowList:
    """The names the page may be reached by: the bind address, `localhost`, and the description's
    `allowed_host` names; with a wildcard bind also this machine's name and any IP address (the
    machine's addresses change with the network, and an address, unlike a name, cannot be rebound
    to another machine by a DNS server)."""

    def __init__(self, bind: str, extra: list[str] | tuple[str, ...] = ()):
        names = {*LOOPBACK_NAMES, *extra}
        self.any_address = bind in WILDCARD_BINDS
        if self.any_address:
            names.add(socket.gethostname())
        else:
            names.add(bind)
        if bind in LOOPBACK_NAMES:
            names.update(LOOPBACK_ADDRESSES)
        self.names = frozenset(_normal(name) for name in names)

    def allows(self, host_header: bytes | None) -> bool:
        if not host_header:
            return False
        name = _normal(_host_of(host_header.decode("latin-1")))
        if name in self.names:
            return True
        return self.any_address and _is_address(name)


def _host_of(header: str) -> str:
    """The name of a Host header without its port (`[::1]:8640` -> `::1`)."""
    if header.startswith("["):
        return header[1:].split("]", 1)[0]
    return header.rsplit(":", 1)[0] if header.count(":") == 1 else header


def _normal(name: str) -> str:
    name = name.strip().lower().removesuffix(".")
    try:
        return str(ipaddress.ip_address(name))
    except ValueError:
        return name


def _is_address(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True


class HostGuard:
    """ASGI middleware: a request whose Host header is not on the allow-list is refused (403), whatever
    its route, so a page of another site that re-points its own name at this machine (DNS rebinding)
    reaches nothing."""

    def __init__(self, app, allowed: HostAllowList):
        self.app = app
        self.allowed = allowed

    async def __call__(self, scope, receive, send):
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        host = dict(scope["headers"]).get(b"host")
        if self.allowed.allows(host):
            return await self.app(scope, receive, send)
        shown = (host or b"").decode("latin-1")[:MAX_HOST_SHOWN_CHARS]
        response = JSONResponse(
            {"error": f"host {shown!r} is not one this dashboard answers to (see allowed_host in its description)"},
            status_code=403,
        )
        return await response(scope, receive, send)
