"""The fleet view for tests: `joshua-fleet` in a process of its own, Zenoh peers that publish what a test
says (with or without credentials), and the certificates the commands of docs/security.md make."""

import json
import re
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

from dashboard_support import SERVER_START_TIMEOUT_S, free_port, get_json, stop

SECURITY_PAGE = Path(__file__).resolve().parents[3] / "docs" / "security.md"
CERTIFICATES_MARKER = "<!-- test: fleet-certificates -->"
CERTIFICATES_BLOCK = re.compile(
    r"^" + re.escape(CERTIFICATES_MARKER) + r"\n```sh\n(.*?)^```$", re.MULTILINE | re.DOTALL
)
CERTIFICATES_TIMEOUT_S = 60
ARRIVAL_TIMEOUT_S = 20.0
POLL_S = 0.1
PEER_SETTLE_S = 0.5  # a peer's session links to the fleet in the background; a put before that is lost


def make_certificates(directory: Path, fleet_san: str, robots: list[str]) -> Path:
    """Run the certificate commands of docs/security.md in `directory`, as a user would; return `directory`."""
    (block,) = CERTIFICATES_BLOCK.findall(SECURITY_PAGE.read_text())
    directory.mkdir(parents=True, exist_ok=True)
    env = {"PATH": "/usr/bin:/bin", "FLEET_SAN": fleet_san, "ROBOTS": " ".join(robots)}
    result = subprocess.run(
        ["bash", "-e", "-c", block],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=CERTIFICATES_TIMEOUT_S,
    )
    assert result.returncode == 0, f"certificate commands of {SECURITY_PAGE.name} failed:\n{block}\n{result.stderr}"
    return directory


class RunningFleet:
    def __init__(self, endpoint: str, url: str, process: subprocess.Popen, log: Path, token: str | None):
        self.endpoint, self.url, self.process, self.log, self.token = endpoint, url, process, log, token

    def robots(self) -> list[dict]:
        return get_json(f"{self.url}/api/robots", self.token)

    def wait_started(self) -> None:
        deadline = time.monotonic() + SERVER_START_TIMEOUT_S
        while True:
            assert self.process.poll() is None, (
                f"joshua-fleet exited with {self.process.returncode}:\n{self.log.read_text()}"
            )
            try:
                self.robots()
                return
            except OSError:
                assert time.monotonic() < deadline, f"joshua-fleet did not answer:\n{self.log.read_text()}"
                time.sleep(POLL_S)

    def names(self) -> set[str]:
        return {robot["name"] for robot in self.robots()}

    def wait_for(self, name: str) -> dict:
        """The entry of robot `name` once /api/robots lists it."""
        deadline = time.monotonic() + ARRIVAL_TIMEOUT_S
        while time.monotonic() < deadline:
            entry = next((robot for robot in self.robots() if robot["name"] == name), None)
            if entry is not None:
                return entry
            time.sleep(POLL_S)
        raise AssertionError(f"{name} never appeared in {self.url}/api/robots:\n{self.log.read_text()}")

    def wait_until(self, predicate) -> list[dict]:
        """The robots /api/robots lists once `predicate(robots)` holds."""
        deadline = time.monotonic() + ARRIVAL_TIMEOUT_S
        while not predicate(robots := self.robots()):
            assert time.monotonic() < deadline, f"/api/robots never came to {robots}:\n{self.log.read_text()}"
            time.sleep(POLL_S)
        return robots

    def wait_until_gone(self, name: str) -> None:
        self.wait_until(lambda robots: name not in {robot["name"] for robot in robots})


@contextmanager
def running_fleet(tmp_path: Path, *arguments: str, scheme: str = "tcp", token: str | None = None):
    """`python -m joshua_runtime.dashboard.fleet --listen SCHEME/127.0.0.1:PORT --port N [--token TOKEN] ARGUMENTS...`."""
    arguments += ("--token", token) if token else ()
    endpoint = f"{scheme}/127.0.0.1:{free_port()}"
    port = free_port()
    log = tmp_path / "fleet.log"
    with open(log, "w") as output:
        process = subprocess.Popen(
            [sys.executable, "-m", "joshua_runtime.dashboard.fleet", "--listen", endpoint, "--port", str(port)]
            + list(arguments),
            stdout=output,
            stderr=subprocess.STDOUT,
        )
    try:
        url = f"http://127.0.0.1:{port}"
        fleet = RunningFleet(endpoint, url, process, log, token)
        fleet.wait_started()
        yield fleet
    finally:
        stop(process)


def run_fleet(*arguments: str) -> subprocess.CompletedProcess:
    """`joshua-fleet ARGUMENTS...` expected to stop at once (a usage or settings error)."""
    return subprocess.run(
        [sys.executable, "-m", "joshua_runtime.dashboard.fleet", *arguments], capture_output=True, text=True, timeout=60
    )


def status(robot: str, nodes=(("leader", "running"),), **extra) -> str:
    """A status as a robot's dashboard publishes it."""
    return json.dumps(
        {
            "robot": robot,
            "nodes": [
                {"name": n, "state": s, "pid": 100, "restarts": 0, "ready": True, "since_s": 1.0} for n, s in nodes
            ],
            "url": f"http://{robot}.example:8640/",
            **extra,
        }
    )


@contextmanager
def zenoh_peer(endpoint: str, user: str | None = None, password: str | None = None, tls: dict | None = None):
    """A Zenoh peer connected to `endpoint` that a test drives by hand: the session, once its link settled.

    `tls`: Zenoh's transport/link/tls settings (root_ca_certificate, connect_certificate, ...)."""
    import zenoh

    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("connect/endpoints", json.dumps([endpoint]))
    config.insert_json5("connect/exit_on_failure", "false")
    config.insert_json5("listen/endpoints", "[]")
    config.insert_json5("scouting/multicast/enabled", "false")
    if user is not None:
        config.insert_json5("transport/auth/usrpwd/user", json.dumps(user))
        config.insert_json5("transport/auth/usrpwd/password", json.dumps(password))
    if tls is not None:
        config.insert_json5("transport/link/tls", json.dumps(tls))
    session = zenoh.open(config)
    try:
        time.sleep(PEER_SETTLE_S)
        yield BlockingPuts(session)
    finally:
        session.close()


class BlockingPuts:
    """A Zenoh session whose puts wait for room in the link's queue: Zenoh drops a put whose queue is full by
    default (on a busy machine, after a few large junk statuses, the good one after them was dropped), and a
    test's puts must all arrive, in order."""

    def __init__(self, session):
        self.session = session

    def put(self, key: str, payload, **options) -> None:
        import zenoh

        options.setdefault("congestion_control", zenoh.CongestionControl.BLOCK)
        self.session.put(key, payload, **options)

    def __getattr__(self, name: str):
        return getattr(self.session, name)


def linked_to_fleet(session) -> bool:
    """True when the peer's session holds a link to the fleet (a router)."""
    return bool(list(session.info.routers_zid()))


def wait_linked(session) -> None:
    deadline = time.monotonic() + ARRIVAL_TIMEOUT_S
    while not linked_to_fleet(session):
        assert time.monotonic() < deadline, "the peer never linked to the fleet"
        time.sleep(POLL_S)
