"""Who may use the API: a bearer token whenever the server listens beyond loopback, and same-origin writes only."""

import hmac
import secrets

from starlette.responses import JSONResponse

from joshua_core.dashboard import is_loopback

TOKEN_BYTES = 24


def required_token(bind: str, given: str | None) -> tuple[str | None, bool]:
    """(token the API requires or None, whether it was generated here and must be shown once)."""
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
