"""`python -m joshua_runtime.dashboard --manifest OUT/manifest.json [...]`: serve a robot's dashboard until SIGINT/SIGTERM."""

import argparse
import asyncio
import os
import socket
import sys
from pathlib import Path

from joshua_core.dashboard import DEFAULT_BIND, DEFAULT_PORT, page_url
from joshua_core.dashboard_token import TOKEN_SUFFIX, TokenFileError, load_or_create_token, token_path
from joshua_runtime.dashboard.zenoh_link import add_credential_arguments
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.notify import Notifier

# The built page: $JOSHUA_WEB_DIR (a container image sets it to the copy it holds), else web/dist of the
# checkout this package lives in (built by `make setup`).
WEB_DIR_VARIABLE = "JOSHUA_WEB_DIR"
DEFAULT_WEB_DIR = Path(os.environ.get(WEB_DIR_VARIABLE) or Path(__file__).resolve().parents[3] / "web" / "dist")
SHUTDOWN_GRACE_S = 1
NOTIFY_POLL_S = 0.05  # how often the start of the server is checked
WATCHDOG_LOOKS = 4  # the watchdog is looked at this often per interval, and pinged once half of it has passed


def port_number(text: str) -> int:
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"must be a port number from 0 to 65535: {text}")
    return port


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="python -m joshua_runtime.dashboard",
        description="Serve a robot's web dashboard (page, status, live data, control).",
    )
    parser.add_argument("--manifest", type=Path, required=True, help="OUT/manifest.json of the robot's build")
    parser.add_argument(
        "--control-socket",
        type=Path,
        metavar="PATH",
        help="the supervisor's control socket (default: $JOSHUA_CONTROL_SOCKET, else "
        "$XDG_RUNTIME_DIR/joshua/ROBOT.sock, else /tmp/joshua-UID/ROBOT.sock)",
    )
    parser.add_argument("--port", type=port_number, default=DEFAULT_PORT, help=f"TCP port (default {DEFAULT_PORT})")
    parser.add_argument(
        "--bind", default=DEFAULT_BIND, metavar="ADDR", help=f"address to listen on (default {DEFAULT_BIND})"
    )
    parser.add_argument(
        "--allowed-host",
        action="append",
        default=[],
        metavar="NAME",
        help="one more name the page may be reached by (the Host header), besides the bind address and "
        "localhost; repeatable",
    )
    parser.add_argument(
        "--token-file",
        type=Path,
        metavar="PATH",
        help=f"file holding the bearer token the API requires, created (mode 0600) when absent "
        f"(default: beside the control socket, ROBOT{TOKEN_SUFFIX})",
    )
    parser.add_argument(
        "--zenoh-connect",
        metavar="ENDPOINT",
        help="also publish status and telemetry over zenoh to this endpoint (tcp/HOST:PORT)",
    )
    add_credential_arguments(parser)
    parser.add_argument("--public-url", metavar="URL", help="the page's address as the fleet view links to it")
    parser.add_argument("--web-dir", type=Path, default=DEFAULT_WEB_DIR, help="the built page (default: web/dist)")
    return parser.parse_args(argv)


def listening_socket(bind: str, port: int) -> socket.socket:
    """A bound, listening TCP socket; a clear error when the address is taken or unknown."""
    from joshua_runtime.dashboard.connections import ACCEPT_BACKLOG

    try:
        family = socket.getaddrinfo(bind, port, type=socket.SOCK_STREAM)[0][0]
        sock = socket.socket(family, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((bind, port))
        sock.listen(ACCEPT_BACKLOG)
    except OSError as exc:
        raise JoshuaError(f"cannot listen on {bind}:{port}: {exc.strerror or exc}") from exc
    sock.setblocking(False)
    return sock


async def serve(args) -> None:
    import uvicorn

    from joshua_runtime.dashboard.app import Dashboard
    from joshua_runtime.dashboard.broadcaster import Broadcaster
    from joshua_runtime.dashboard.connections import ACCEPT_BACKLOG, KEEP_ALIVE_S, connection_limit, guarded_protocol
    from joshua_runtime.dashboard.control_client import default_socket_path
    from joshua_runtime.dashboard.log_limit import configure_logging
    from joshua_runtime.dashboard.robot_view import load_robot_view
    from joshua_runtime.dashboard.security import HostAllowList
    from joshua_runtime.dashboard.server import StoppingAwareServer
    from joshua_runtime.dashboard.zenoh_link import FleetLink, check_endpoint, credentials_of, robot_settings
    from joshua_runtime.hosts.client import control_client

    view = load_robot_view(args.manifest)
    if args.zenoh_connect:
        check_endpoint(args.zenoh_connect)
    fleet_settings = robot_settings(view.robot, args.zenoh_connect or "", credentials_of(args))
    control_socket = args.control_socket or default_socket_path(view.robot)
    token_file = args.token_file or token_path(control_socket)
    try:
        token = load_or_create_token(token_file)
    except TokenFileError as exc:
        raise SettingsError(str(exc)) from exc
    sock = listening_socket(args.bind, args.port)
    port = sock.getsockname()[1]
    url = args.public_url or page_url(args.bind, port)
    # ROS is loaded once the settings are known to be good, so that a mistake in them is told in one line also
    # where rclpy is not importable (apt's ROS not sourced).
    from joshua_runtime.dashboard.frame_memory import set_up_for_frames
    from joshua_runtime.dashboard.telemetry import Telemetry

    set_up_for_frames()
    broadcaster = Broadcaster()
    telemetry = Telemetry(view, broadcaster)
    control = control_client(args.manifest, control_socket)
    allowed = HostAllowList(args.bind, args.allowed_host)
    dashboard = Dashboard(view, control, broadcaster, telemetry, args.web_dir, token, allowed)
    link = FleetLink(view.robot, args.zenoh_connect, url, broadcaster, fleet_settings) if args.zenoh_connect else None
    # The address without the token: this line ends up in the node's log (`joshuac run` prints it with).
    print(f"dashboard of {view.robot}: {url} (its access token is in {token_file})", flush=True)
    rate_limit = configure_logging()
    telemetry.start()
    link_task = asyncio.create_task(link.run()) if link else None
    config = uvicorn.Config(
        dashboard.app,
        log_config=None,
        access_log=False,
        timeout_graceful_shutdown=SHUTDOWN_GRACE_S,
        lifespan="on",
        http=guarded_protocol(connection_limit()),
        timeout_keep_alive=KEEP_ALIVE_S,
        backlog=ACCEPT_BACKLOG,
    )
    server = StoppingAwareServer(config, dashboard.note_stopping)
    notifier = Notifier.from_environment()
    notify_task = asyncio.create_task(notify_manager(server, notifier, url))
    try:
        await server.serve(sockets=[sock])
    finally:
        notify_task.cancel()
        notifier.stopping()
        if link_task:
            link_task.cancel()
            link.close()
        for line in rate_limit.pending():
            print(f"dashboard: {line}", file=sys.stderr, flush=True)
        telemetry.close()  # the last: it may end the process (ros_teardown.py)


async def notify_manager(server, notifier, url: str) -> None:
    """READY=1 to the process manager (supervisor.py, systemd) once the server listens, then the
    watchdog's pings while the event loop runs (when the manager asks for them)."""
    while not server.started:
        await asyncio.sleep(NOTIFY_POLL_S)
    notifier.ready(f"serving {url}")
    if notifier.watchdog_interval_s is None:
        return
    while True:
        notifier.watchdog()
        await asyncio.sleep(notifier.watchdog_interval_s / WATCHDOG_LOOKS)


def main(argv=None) -> int:
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        asyncio.run(serve(args))
    except JoshuaError as exc:
        print(f"dashboard: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        pass
    return 0
