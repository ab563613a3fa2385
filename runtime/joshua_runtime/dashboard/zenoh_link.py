"""Zenoh for the fleet view: session settings, and the robot side that publishes under `joshua/<robot>/...`.

Keys: `joshua/<robot>/status` (the supervisor's status plus the dashboard's `url`), `joshua/<robot>/rates`,
`joshua/<robot>/joints/<topic>`, `joshua/<robot>/recorder/<node>`, `joshua/<robot>/inference/<node>`.
Camera frames and scans stay on the robot's own page. A dashboard that stops deletes its status key, so the
fleet view shows the robot offline at once rather than once it has been silent long enough. Multicast scouting is off: peers meet only
through the endpoints given. A robot presents the credentials its description names (a password read
from a file, its user being the robot's name; TLS certificates by path) and the fleet view admits it
only under `joshua/<its name>/` (see fleet_access.py).
"""

import asyncio
import json
import threading

from joshua_core.dashboard import (
    FLEET_CREDENTIAL_FIELDS,
    credential_flag,
    fleet_credential_problems,
    zenoh_endpoint_problem,
)
from joshua_runtime.dashboard.api_schema import event_kind
from joshua_runtime.errors import SettingsError

KEY_ROOT = "joshua"
# The events of /api/events the fleet view also gets (camera frames and scans stay on the robot).
PUBLISHED_KINDS = tuple(event_kind(kind) for kind in ("status", "rates", "joints", "recorder", "inference"))


def check_endpoint(endpoint: str) -> str:
    """The endpoint when it reads `tcp/HOST:PORT` (or udp, quic, tls) with a port in 1..65535."""
    problem = zenoh_endpoint_problem(endpoint)
    if problem:
        raise SettingsError(problem)
    return endpoint


def open_session(mode: str, connect: list[str] = (), listen: list[str] = (), settings: dict | None = None):
    """A zenoh session in `mode` (peer, router), without multicast scouting, with `settings` (zenoh
    configuration key -> value) on top.

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
        for key, value in (settings or {}).items():
            config.insert_json5(key, json.dumps(value))
        return zenoh.open(config)
    except zenoh.ZError as exc:
        raise SettingsError(f"zenoh: {exc}") from exc


def add_credential_arguments(parser) -> None:
    """The dashboard's `--zenoh-password-file PATH`, `--zenoh-tls-ca PATH`, ... (the description's fields)."""
    for field in FLEET_CREDENTIAL_FIELDS:
        parser.add_argument(
            credential_flag(field), dest=field, default="", metavar="PATH", help=f"the description's {field}"
        )


def credentials_of(args) -> dict[str, str]:
    return {field: getattr(args, field) for field in FLEET_CREDENTIAL_FIELDS}


def robot_settings(robot: str, endpoint: str, credentials: dict[str, str]) -> dict:
    """The zenoh settings that present `robot`'s credentials (field -> path) to the fleet view at `endpoint`.

    The password is read here, into the session's settings only; the TLS files are checked readable and
    handed to zenoh by path.
    """
    problems = fleet_credential_problems(endpoint, credentials)
    if problems:
        raise SettingsError(problems[0][1])
    settings = {}
    if credentials["zenoh_password_file"]:
        settings["transport/auth/usrpwd/user"] = robot
        settings["transport/auth/usrpwd/password"] = read_password(credentials["zenoh_password_file"])
    if credentials["zenoh_tls_ca"]:
        settings["transport/link/tls/root_ca_certificate"] = readable("zenoh_tls_ca", credentials["zenoh_tls_ca"])
    if credentials["zenoh_tls_certificate"]:
        certificate = readable("zenoh_tls_certificate", credentials["zenoh_tls_certificate"])
        settings["transport/link/tls/connect_certificate"] = certificate
        settings["transport/link/tls/connect_private_key"] = readable(
            "zenoh_tls_private_key", credentials["zenoh_tls_private_key"]
        )
        settings["transport/link/tls/enable_mtls"] = True
    return settings


def readable(field: str, path: str) -> str:
    """`path` once it opens for reading (a clear error now rather than a refused link later)."""
    try:
        with open(path, "rb"):
            return path
    except OSError as exc:
        raise SettingsError(f"cannot read {field} {path}: {exc.strerror or exc}") from exc


def read_password(path: str) -> str:
    """The one-line password in the file at `path` (a final newline allowed)."""
    try:
        with open(readable("zenoh_password_file", path), encoding="utf-8") as file:
            text = file.read()
    except UnicodeDecodeError as exc:
        raise SettingsError(f"zenoh_password_file {path} is not UTF-8 text") from exc
    password = text.removesuffix("\n")
    if not password or password != password.strip() or "\n" in password:
        raise SettingsError(f"zenoh_password_file {path} must hold one line, the password, without surrounding spaces")
    return password


def key_for(robot: str, event_key: str) -> str:
    """The zenoh key of a broadcaster key: `joints:/leader/joint_states` -> `joshua/R/joints/leader/joint_states`."""
    kind, _, name = event_key.partition(":")
    parts = [KEY_ROOT, robot, kind, *[part for part in name.split("/") if part]]
    return "/".join(parts)


class FleetLink:
    """Forwards the broadcaster's events (all but images and scans) to zenoh, through a mailbox of its own;
    withdraws the robot's status when it closes."""

    def __init__(self, robot: str, endpoint: str, url: str, broadcaster, settings: dict | None = None):
        self.robot = robot
        self.url = url
        self.broadcaster = broadcaster
        self.session = open_session("peer", connect=[check_endpoint(endpoint)], settings=settings)
        self._publishing = threading.Lock()  # a put still under way in its thread never follows the withdrawal
        self._withdrawn = False

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
                await asyncio.to_thread(self.put, key_for(self.robot, key), payload)
        finally:
            self.broadcaster.unsubscribe(mailbox)

    def put(self, key: str, payload) -> None:
        """Put `payload` under `key`, unless the robot's status was withdrawn (the link is closing)."""
        with self._publishing:
            if not self._withdrawn:
                self.session.put(key, payload)

    def close(self) -> None:
        """Delete the robot's status key (the fleet view shows it offline now), then leave the session."""
        with self._publishing:
            self._withdrawn = True
            self.session.delete(key_for(self.robot, "status"))
        self.session.close()
