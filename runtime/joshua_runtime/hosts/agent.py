"""`python -m joshua_runtime.hosts.agent --manifest OUT/hosts/H/manifest.json [...]`: the agent of one host.

The generated process `host_agent_<host>` on every host of a robot on several. It
- watches the robot's Discovery Server (when there is one) and tells its supervisor (server_watch.py);
- serves the local socket `<name>.hosts.sock` beside the control socket (relay.py), through which
  `supervisor.py ctl --host NAME`, `ctl status --all-hosts` and the dashboard reach every host;
- with `--listen ENDPOINT` (the control host) or `--connect ENDPOINT` (the others), joins the other hosts'
  agents over authenticated Zenoh (link.py, access.py): publishes its host's status every second, hears the
  others', and answers the control requests of the other hosts for its own supervisor.
It says READY=1 once its socket serves, and exits 0 on SIGINT or SIGTERM.
"""

import argparse
import asyncio
import json
import os
import signal
import sys
import time
from pathlib import Path

from joshua_core import control_plane
from joshua_runtime.dashboard.control_client import ControlClient, ControlError, default_socket_path
from joshua_runtime.dashboard.zenoh_link import check_endpoint
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.hosts import access
from joshua_runtime.hosts.link import HostsLink
from joshua_runtime.hosts.relay import Relay
from joshua_runtime.hosts.requests import Request, RequestRefused, parse, parse_remote, refusal
from joshua_runtime.hosts.roster import STATUS_PERIOD_S, Placement, Roster
from joshua_runtime.hosts.server_watch import DiscoveryWatch
from joshua_runtime.notify import Notifier

WATCHDOG_PERIOD_S = 1.0
DROPPED_LOG_PERIOD_S = 10.0  # statuses of another host dropped for their form are logged at most this often
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog=f"python -m {control_plane.RUNTIME_MODULE}", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--manifest", type=Path, required=True, help="this host's manifest.json")
    role = parser.add_mutually_exclusive_group()
    role.add_argument("--listen", metavar="ENDPOINT", help="be the router the other hosts connect to (tcp/ADDR:PORT)")
    role.add_argument("--connect", metavar="ENDPOINT", help="connect to the router at ENDPOINT")
    for field in control_plane.CREDENTIAL_FIELDS:
        parser.add_argument(control_plane.credential_flag(field), dest=field, default="", metavar="PATH")
    parser.add_argument("--control-socket", type=Path, metavar="PATH", help="the supervisor's control socket")
    parser.add_argument(
        "--hosts-socket",
        type=Path,
        metavar="PATH",
        default=os.environ.get(control_plane.HOSTS_SOCKET_VARIABLE) or None,
        help=f"serve the local socket here (default: ${control_plane.HOSTS_SOCKET_VARIABLE}, which the supervisor "
        "sets when it serves its control socket)",
    )
    return parser.parse_args(argv)


def load_manifest(path: Path) -> tuple[Placement, dict | None]:
    """The hosts' placement and the Discovery Server (None without one) of this host's manifest."""
    try:
        manifest = json.loads(path.read_text())
        return Placement.from_manifest(manifest), manifest.get("discovery")
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise SettingsError(f"{path} is not the manifest of one host of a robot on several: {exc}") from exc


class Agent:
    def __init__(self, args, placement: Placement, notifier: Notifier):
        self.placement = placement
        self.host = placement.host
        self.notifier = notifier
        control_socket = args.control_socket or default_socket_path(f"{placement.robot}.{self.host}")
        self.supervisor = ControlClient(control_socket)
        endpoint = args.listen or args.connect
        self.roster = Roster(placement, linked=bool(endpoint))
        self.link = None
        if endpoint:
            check_endpoint(endpoint)
            credentials = access.Credentials.from_arguments(args)
            settings = (
                access.router_settings(placement.robot, placement.host_names, credentials)
                if args.listen
                else access.client_settings(self.host, credentials)
            )
            self.link = HostsLink(
                placement.robot, self.host, endpoint, bool(args.listen), settings, self._heard, self._queried
            )
        # A supervisor run without a control socket (--no-control) names none: then no one is served here.
        self.relay = Relay(args.hosts_socket, self._relay_request) if args.hosts_socket else None
        self.loop = None
        self.dropped, self.dropped_logged_at = 0, None

    async def run(self, stop: asyncio.Event, discovery) -> None:
        self.loop = asyncio.get_running_loop()
        if self.relay is not None:
            await self.relay.start()
        if self.link is not None:
            self.link.start()
        if discovery is not None:
            discovery.start()
        serving = f"serving {self.relay.path}" if self.relay else "no control socket, so no local socket"
        joined = f"joins the other hosts at {self.link.endpoint}" if self.link else "no control plane"
        self.notifier.ready(f"{serving}; {joined}")
        print(f"{control_plane.process_name(self.host)}: {serving}; {joined}", flush=True)
        tasks = [asyncio.create_task(self._report()), asyncio.create_task(self._watchdog())]
        try:
            await stop.wait()
        finally:
            for task in tasks:
                task.cancel()
            if self.relay is not None:
                self.relay.close()
            if self.link is not None:
                await asyncio.to_thread(self.link.close)

    async def _report(self) -> None:
        """This host's status, every STATUS_PERIOD_S: kept, and published to the other hosts."""
        while True:
            now = time.monotonic()
            try:
                reply = await self.supervisor.reply({"command": "status"})
            except ControlError as exc:
                self.roster.record_error(self.host, f"its supervisor does not answer: {exc}")
            else:
                if reply.pop("ok", False) and self.roster.record(self.host, reply, now) and self.link is not None:
                    await asyncio.to_thread(self.link.publish, reply)
            await asyncio.sleep(STATUS_PERIOD_S)

    async def _watchdog(self) -> None:
        while True:
            self.notifier.watchdog()
            await asyncio.sleep(WATCHDOG_PERIOD_S)

    def _heard(self, host: str, status) -> None:
        """A status published by another host (a Zenoh thread)."""
        if host != self.host and self.loop is not None:
            self.loop.call_soon_threadsafe(self._record, host, status)

    def _record(self, host: str, status) -> None:
        now = time.monotonic()
        if self.roster.record(host, status, now):
            return
        self.dropped += 1
        if self.dropped_logged_at is None or now - self.dropped_logged_at >= DROPPED_LOG_PERIOD_S:
            self.dropped_logged_at = now
            print(
                f"{control_plane.process_name(self.host)}: dropped a status of host {host} that is not one of its "
                f"supervisor ({self.dropped} so far)",
                flush=True,
            )

    def _queried(self, query) -> None:
        """A control request of another host for this host's supervisor (a Zenoh thread): answered later."""
        try:
            asyncio.run_coroutine_threadsafe(self._answer(query), self.loop)
        except (RuntimeError, TypeError):  # the agent is stopping (or not started): the query goes unanswered
            query.drop()

    async def _answer(self, query) -> None:
        payload = query.payload.to_bytes() if query.payload is not None else b""
        try:
            reply = await self._supervisor_reply(parse_remote(payload, self.host))
        except RequestRefused as exc:
            reply = exc.reply()
        await asyncio.to_thread(self.link.answer, query, reply)

    async def _supervisor_reply(self, request: Request) -> dict:
        try:
            return await self.supervisor.reply(request.forwarded, request.relayed_wait_s())
        except ControlError as exc:
            return refusal("unreachable", f"the supervisor of host {self.host} does not answer: {exc}")

    async def _relay_request(self, line: bytes) -> dict:
        """A request on the local socket: this host's supervisor, another host's over Zenoh, or every host's status."""
        try:
            request = parse(line, self.host, self.placement.host_names)
        except RequestRefused as exc:
            return exc.reply()
        if request.all_hosts:
            return {"ok": True, **self.roster.aggregate(time.monotonic())}
        if request.host == self.host:
            return await self._supervisor_reply(request)
        if self.link is None:
            return refusal(
                "unreachable",
                f"host {request.host} cannot be reached from here: the description has no `control {{ }}`",
            )
        reply = await asyncio.to_thread(self.link.ask, request.host, request.remote(), request.relayed_wait_s())
        if reply is None:
            return refusal("unreachable", f"host {request.host} did not answer: {self._why_silent(request.host)}")
        return reply

    def _why_silent(self, host: str) -> str:
        if not self.link.connected:
            return f"this host has not reached the router at {self.link.endpoint} yet"
        return self.roster.silence(host, time.monotonic()) or "its agent gave no reply in time"


async def serve(args) -> None:
    placement, server = load_manifest(args.manifest)
    notifier = Notifier.from_environment()
    agent = Agent(args, placement, notifier)
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for number in STOP_SIGNALS:
        loop.add_signal_handler(number, stop.set)
    discovery = DiscoveryWatch(server["address"], server["port"], notifier, sys.stdout) if server else None
    try:
        await agent.run(stop, discovery)
    finally:
        notifier.stopping()
        if discovery is not None:
            discovery.close()


def main(argv=None) -> int:
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        asyncio.run(serve(args))
    except JoshuaError as exc:
        print(f"host agent: error: {exc}", file=sys.stderr, flush=True)
        return exc.exit_code
    return 0


if __name__ == "__main__":
    sys.exit(main())
