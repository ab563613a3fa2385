"""`joshua-fleet --listen tcp/HOST:PORT --port N`: the fleet page and `GET /api/robots` for every robot that
publishes its status over zenoh under `joshua/<robot>/status` (see zenoh_link.py); a robot that deletes that
key (its dashboard stopped) is listed offline at once.

`GET /api/robots` answers a JSON list, one entry per robot, sorted by name:
`{"name", "nodes": [{"name", "state", "pid", ...}], "last_seen_s", "online", "url", "error", "release", "health",
"rollout"}` (url: the robot's own page, http or https; release: `{"build", "built"}` of what it runs; health:
`{"ready", "of"}` nodes; rollout: its computers' entries in the last rollout of `joshua-fleet deploy`, whose
state file --rollout-state names, or null; the shape: `FleetRobots` of api.schema.json). `GET /api/rollout`
answers that rollout's summary (`FleetRollout`). Zenoh admits only the robots named by the access flags
(fleet_access.py); each status is checked against fleet_status.py's schema before the roster (fleet_roster.py)
keeps it.
The same token rule as the robot's dashboard applies: beyond loopback, /api/ needs the bearer token.
"""

import argparse
import sys
import threading
import time
from pathlib import Path

from starlette.applications import Starlette
from starlette.responses import FileResponse, JSONResponse, PlainTextResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from joshua_runtime.dashboard.cli import (
    DEFAULT_BIND,
    DEFAULT_WEB_DIR,
    SHUTDOWN_GRACE_S,
    listening_socket,
    port_number,
)
from joshua_runtime.dashboard.fleet_access import FleetAccess
from joshua_runtime.dashboard.fleet_allocator import map_large_blocks_alone
from joshua_runtime.dashboard.fleet_rollout import RolloutView
from joshua_runtime.dashboard.fleet_roster import DEFAULT_FORGET_AFTER_S, DEFAULT_OFFLINE_AFTER_S, MAX_ROBOTS, Roster
from joshua_runtime.dashboard.fleet_status import StatusRejected, check_size, read_status
from joshua_runtime.dashboard.security import ApiGuard, required_token
from joshua_runtime.dashboard.zenoh_link import KEY_ROOT, check_endpoint, open_session
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.rollout.state import default_state_path

DEFAULT_PORT = 8650
STATUS_KEYS = f"{KEY_ROOT}/*/status"
DROP_REPORT_PERIOD_S = 10.0  # dropped statuses are counted and reported at most this often
# The page runs only its own scripts: a link or text from a robot can never become code.
PAGE_POLICY = (
    "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
    "connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'; form-action 'none'"
)


class StatusListener:
    """Zenoh's callback: reads each status through the schema into the roster, takes a deleted status as the
    robot going offline, and reports what it drops."""

    def __init__(self, roster: Roster):
        from zenoh import SampleKind

        self.roster = roster
        self._deleted = SampleKind.DELETE
        self._lock = threading.Lock()
        self._dropped = 0
        self._last_reason = ""
        self._last_report = float("-inf")

    def receive(self, sample) -> None:
        robot = str(sample.key_expr).split("/")[1]
        if sample.kind == self._deleted:
            self.roster.withdraw(robot)
            return
        try:
            check_size(len(sample.payload))
            status = read_status(robot, sample.payload.to_bytes())
        except StatusRejected as exc:
            self._drop(robot, str(exc))
            return
        if not self.roster.update(robot, status):
            self._drop(robot, f"the roster is full ({MAX_ROBOTS} robots)")

    def _drop(self, robot: str, reason: str) -> None:
        now = time.monotonic()
        with self._lock:
            self._dropped += 1
            self._last_reason = f"{robot[:80]!r}: {reason}"
            if now - self._last_report < DROP_REPORT_PERIOD_S:
                return
            dropped, self._dropped, self._last_report = self._dropped, 0, now
        print(
            f"fleet: dropped {dropped} status(es) since the last report; the last, of {self._last_reason}", flush=True
        )


def fleet_app(roster: Roster, web_dir: Path, token: str | None, rollout: RolloutView | None = None) -> Starlette:
    rollout = rollout or RolloutView(None)

    async def page(_request):
        index = web_dir / "fleet.html"
        if not index.is_file():
            return PlainTextResponse(f"the page is not built ({index} is missing): run `make setup`", status_code=503)
        return FileResponse(index, headers={"Content-Security-Policy": PAGE_POLICY})

    async def robots(_request):
        return Response(roster.robots_json(rollout.by_robot()), media_type="application/json")

    async def last_rollout(_request):
        return JSONResponse(rollout.summary())

    routes = [Route("/", page), Route("/api/robots", robots), Route("/api/rollout", last_rollout)]
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
    access = parser.add_argument_group("who may publish (docs/security.md, Fleet); without these, loopback only")
    access.add_argument("--users", metavar="FILE", help="zenoh user/password file: one ROBOT:PASSWORD a line")
    access.add_argument("--tls-certificate", metavar="FILE", help="the fleet's TLS certificate (PEM), with tls/")
    access.add_argument("--tls-private-key", metavar="FILE", help="the key of --tls-certificate (PEM)")
    access.add_argument("--tls-ca", metavar="FILE", help="CA of the robots' certificates (PEM): mutual TLS")
    access.add_argument("--robots", metavar="FILE", help="with --tls-ca: robot names, one a line (= certificate CN)")
    parser.add_argument(
        "--rollout-state",
        type=Path,
        default=None,
        metavar="FILE",
        help="the state file of joshua-fleet deploy, whose rollout the page shows (default: the one deploy writes)",
    )
    roster = parser.add_argument_group("robots not heard from")
    roster.add_argument(
        "--offline-after",
        type=float,
        default=DEFAULT_OFFLINE_AFTER_S,
        metavar="S",
        help=f"shown offline after S seconds (default {DEFAULT_OFFLINE_AFTER_S:g})",
    )
    roster.add_argument(
        "--forget-after",
        type=float,
        default=DEFAULT_FORGET_AFTER_S,
        metavar="S",
        help=f"removed after S seconds (default {DEFAULT_FORGET_AFTER_S:g})",
    )
    return parser.parse_args(argv)


def check_durations(offline_after_s: float, forget_after_s: float) -> None:
    if not 0 < offline_after_s < float("inf"):
        raise SettingsError(f"--offline-after must be a number above 0 (it is {offline_after_s:g})")
    if not offline_after_s < forget_after_s < float("inf"):
        raise SettingsError(
            f"--forget-after ({forget_after_s:g} s) must be longer than --offline-after ({offline_after_s:g} s)"
        )


def main(argv=None) -> int:
    import asyncio

    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] in ("deploy", "rollback"):
        from joshua_runtime.rollout.cli import main as rollout_main

        return rollout_main(argv)

    import uvicorn

    from joshua_runtime.dashboard.server import SelfEndingServer

    args = parse_arguments(argv)
    session = None
    try:
        check_endpoint(args.listen)
        check_durations(args.offline_after, args.forget_after)
        access = FleetAccess.from_arguments(args)
        token, generated = required_token(args.bind, args.token)
        sock = listening_socket(args.bind, args.port)
        map_large_blocks_alone()
        roster = Roster(args.offline_after, args.forget_after)
        session = open_session("router", listen=[args.listen], settings=access.zenoh_settings())
        subscriber = session.declare_subscriber(STATUS_KEYS, StatusListener(roster).receive)
        url = f"http://{args.bind}:{sock.getsockname()[1]}/"
        admitted = f"{len(access.robots)} robots admitted by name" if access.robots else "any peer on this machine"
        print(
            f"fleet: {url}" + (f"#token={token}" if generated else "") + f" (robots connect to {args.listen}; "
            f"{admitted})",
            flush=True,
        )
        if generated:
            print(f"fleet: API token (shown once): {token}", flush=True)
        config = uvicorn.Config(
            fleet_app(roster, args.web_dir, token, RolloutView(args.rollout_state or default_state_path())),
            log_level="warning",
            timeout_graceful_shutdown=SHUTDOWN_GRACE_S,
        )
        asyncio.run(SelfEndingServer(config).serve(sockets=[sock]))
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
