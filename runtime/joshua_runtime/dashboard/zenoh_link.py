"""Zenoh for the fleet view: session settings, and the robot side that publishes under `joshua/<robot>/...`.

Keys: `joshua/<robot>/status` (the supervisor's status plus the dashboard's `url`), `joshua/<robot>/rates`,
`joshua/<robot>/joints/<topic>`, `joshua/<robot>/recorder/<node>`, `joshua/<robot>/inference/<node>`.
Camera frames and scans stay on the robot's own page. Multicast scouting is off: peers meet only
through the endpoints given.
"""

import asyncio
import json

from joshua_core.dashboard import zenoh_endpoint_problem
from joshua_runtime.errors import SettingsError

KEY_ROOT = "joshua"
PUBLISHED_KINDS = ("status", "rates", "joints", "recorder", "inference")


def check_endpoint(endpoint: str) -> str:
    """The endpoint when it reads `tcp/HOST:PORT` (or udp, quic, tls) with a port in 1..65535."""
    problem = zenoh_endpoint_problem(endpoint)
    if problem:
        raise SettingsError(problem)
    return endpoint


def open_session(mode: str, connect: list[str] = (), listen: list[str] = ()):
    """A zenoh session in `mode` (peer, router), without multicast scouting.

    A peer keeps trying its `connect` endpoints in the background: a robot starts whether or not the
    fleet view is up, and appears there once it is.
    """
    import zenoh

    config = zenoh.Config()
    config.insert_json5("mode", json.dumps(mode))
    config.insert_json5("connect/endpoints", json.dumps(list(connect)))
    config.insert_json5("connect/exit_on_failure", "false")
    config.insert_json5("listen/endpoints", json.dumps(list(listen) if listen else []))
    config.insert_json5("scouting/multicast/enabled", "false")
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        raise SettingsError(f"zenoh: {exc}") from exc


def key_for(robot: str, event_key: str) -> str:
    """The zenoh key of a broadcaster key: `joints:/leader/joint_states` -> `joshua/R/joints/leader/joint_states`."""
    kind, _, name = event_key.partition(":")
    parts = [KEY_ROOT, robot, kind, *[part for part in name.split("/") if part]]
    return "/".join(parts)


class FleetLink:
    """Forwards the broadcaster's events (all but images and scans) to zenoh, through a mailbox of its own."""

    def __init__(self, robot: str, endpoint: str, url: str, broadcaster):
        self.robot = robot
        self.url = url
        self.broadcaster = broadcaster
        self.session = open_session("peer", connect=[check_endpoint(endpoint)])

    async def run(self) -> None:
        mailbox = self.broadcaster.subscribe(viewer=False)
        try:
            while True:
                key, event = await mailbox.get_with_key()
                if event.kind not in PUBLISHED_KINDS:
                    continue
                payload = event.data
                if event.kind == "status":
                    payload = json.dumps(dict(json.loads(payload), robot=self.robot, url=self.url))
                await asyncio.to_thread(self.session.put, key_for(self.robot, key), payload)
        finally:
            self.broadcaster.unsubscribe(mailbox)

    def close(self) -> None:
        self.session.close()
