"""`joshua-fleet --listen tcp/HOST:PORT --port N`: the fleet page and `GET /api/robots` for every robot that
publishes its status over zenoh under `joshua/<robot>/status` (see zenoh_link.py).

`GET /api/robots` answers a JSON list, one entry per robot, sorted by name:
`{"name", "nodes": [{"name", "state", "pid", ...}], "last_seen_s", "url"}` (url: the robot's own page).
The same token rule as the robot's dashboard applies: beyond loopback, /api/ needs the bearer token.
"""

import argparse
import json
import sys
import threading
import time
from pathlib import Path

from starlette.applications import Starlette
from starlette.responses import FileResponse, JSONResponse, PlainTextResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from joshua_runtime.dashboard.cli import (
    DEFAULT_BIND,
    DEFAULT_WEB_DIR,
    SHUTDOWN_GRACE_S,
    listening_socket,
    port_number,
)
from joshua_runtime.dashboard.security import ApiGuard, required_token
from joshua_runtime.dashboard.zenoh_link import KEY_ROOT, check_endpoint, open_session
from joshua_runtime.errors import JoshuaError

DEFAULT_PORT = 8650
STATUS_KEYS = f"{KEY_ROOT}/*/status"


class Fleet:
    """The last status of every robot heard from, updated by zenoh's callback thread."""

    def __init__(self):
        self._lock = threading.Lock()
        self._robots: dict[str, tuple[dict, float]] = {}

    def receive(self, sample) -> None:
        robot = str(sample.key_expr).split("/")[1]
        try:
            status = json.loads(sample.payload.to_string())
        except ValueError:
            return
        with self._lock:
            self._robots[robot] = (status, time.monotonic())

    def robots(self) -> list[dict]:
        now = time.monotonic()
        with self._lock:
            entries = sorted(self._robots.items())
        return [
            {
                "name": name,
                "nodes": status.get("nodes") or [],
                "last_seen_s": round(now - seen, 3),
                "url": status.get("url"),
                "error": status.get("error"),
            }
            for name, (status, seen) in entries
        ]


def fleet_app(fleet: Fleet, web_dir: Path, token: str | None) -> Starlette:
    async def page(_request):
        index = web_dir / "fleet.html"
        if not index.is_file():
            return PlainTextResponse(f"the page is not built ({index} is missing): run `make setup`", status_code=503)
        return FileResponse(index)

    async def robots(_request):
        return JSONResponse(fleet.robots())

    routes = [Route("/", page), Route("/api/robots", robots)]
    if (web_dir / "assets").is_dir():
        routes.append(Mount("/assets", StaticFiles(directory=web_dir / "assets")))
    app = Starlette(routes=routes)
    app.add_middleware(ApiGuard, token=token)
    return app


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="joshua-fleet", description="Serve the fleet view of every robot publishing over zenoh."
    )
    parser.add_argument(
        "--listen", required=True, metavar="ENDPOINT", help="zenoh endpoint robots connect to (tcp/HOST:PORT)"
    )
    parser.add_argument("--port", type=port_number, default=DEFAULT_PORT, help=f"HTTP port (default {DEFAULT_PORT})")
    parser.add_argument("--bind", default=DEFAULT_BIND, metavar="ADDR", help=f"HTTP address (default {DEFAULT_BIND})")
    parser.add_argument("--token", help="bearer token for /api/ (generated and printed once beyond loopback)")
    parser.add_argument("--web-dir", type=Path, default=DEFAULT_WEB_DIR, help="the built page (default: web/dist)")
    return parser.parse_args(argv)


def main(argv=None) -> int:
    import asyncio

    import uvicorn

    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    session = None
    try:
        check_endpoint(args.listen)
        token, generated = required_token(args.bind, args.token)
        sock = listening_socket(args.bind, args.port)
        fleet = Fleet()
        session = open_session("router", listen=[args.listen])
        subscriber = session.declare_subscriber(STATUS_KEYS, fleet.receive)
        url = f"http://{args.bind}:{sock.getsockname()[1]}/"
        print(
            f"fleet: {url}" + (f"#token={token}" if generated else "") + f" (robots connect to {args.listen})",
            flush=True,
        )
        if generated:
            print(f"fleet: API token (shown once): {token}", flush=True)
        config = uvicorn.Config(
            fleet_app(fleet, args.web_dir, token), log_level="warning", timeout_graceful_shutdown=SHUTDOWN_GRACE_S
        )
        asyncio.run(uvicorn.Server(config).serve(sockets=[sock]))
        subscriber.undeclare()
    except JoshuaError as exc:
        print(f"joshua-fleet: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        pass
    finally:
        if session is not None:
            session.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
