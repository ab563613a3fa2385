"""A robot on two hosts of this machine, for tests and benchmarks of its control plane.

Host "arm" (127.0.0.1) runs the Discovery Server, a mock leader arm and the control plane's router; host "gpu"
(127.0.0.2) runs a mock follower that reads the leader, and the dashboard. Each host's part runs as its
generated supervisor.py with a control socket of its own, as on two computers. The hosts' credentials are
made by the commands of docs/across-computers.md; each host's part comes from a build whose `control { }` names that host's
files (on real computers one path holds each host's own file).
"""

import contextlib
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

from joshua_core.dashboard_token import token_path
from testsupport.joshuac_cli import ROOT, joshuac
from testsupport.ros_domains import claimed_domain

HOSTS = {"arm": "127.0.0.1", "gpu": "127.0.0.2"}
ROUTER = "arm"
CONTROL_PLANE_PAGE = ROOT / "docs" / "across-computers.md"  # holds the credential commands
COMMANDS_TIMEOUT_S = 60
START_TIMEOUT_S = 90.0
STOP_TIMEOUT_S = 20.0
POLL_S = 0.1
CTL_TIMEOUT_S = 40.0
HTTP_TIMEOUT_S = 30.0

DESCRIPTION = """robot_config {{
  name: "split"
  mode: MODE_TELEOPERATION
  host {{ name: "arm" address: "127.0.0.1" }}
  host {{ name: "gpu" address: "127.0.0.2" }}
  discovery {{ server_host: "arm" port: {discovery_port} }}
  control {{ port: {control_port} {credentials} }}
  dashboard {{ host: "gpu" port: {dashboard_port} }}
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 20 }}
  node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER host: "gpu" topic_name: "/leader/joint_states" rate_hz: 20 }}
  {more_nodes}
}}
"""


def free_port(kind=socket.SOCK_STREAM) -> int:
    with socket.socket(socket.AF_INET, kind) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def page_block(marker: str) -> str:
    """The ```sh block after `<!-- test: MARKER -->` in CONTROL_PLANE_PAGE."""
    pattern = re.compile(r"^<!-- test: " + re.escape(marker) + r" -->\n```sh\n(.*?)^```$", re.MULTILINE | re.DOTALL)
    (block,) = pattern.findall(CONTROL_PLANE_PAGE.read_text())
    return block


def run_page_commands(marker: str, directory: Path, hosts: str) -> Path:
    """Run the page's credential commands in `directory` for `hosts` (their HOSTS variable), as a user would."""
    directory.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(
        ["bash", "-e", "-c", page_block(marker)],
        cwd=directory,
        env={"PATH": "/usr/bin:/bin", "HOSTS": hosts},
        capture_output=True,
        text=True,
        timeout=COMMANDS_TIMEOUT_S,
    )
    assert done.returncode == 0, f"commands {marker} of {CONTROL_PLANE_PAGE.name} failed:\n{done.stderr}"
    return directory


def password_credentials(directory: Path) -> dict[str, str]:
    """Each host's `control { }` credentials with passwords made by the page's commands."""
    run_page_commands("control-passwords", directory, " ".join(HOSTS))
    return {
        host: f'password_file: "{directory / f"{host}.control-password"}" '
        f'users_file: "{directory / "control-users.txt"}"'
        for host in HOSTS
    }


def tls_credentials(directory: Path) -> dict[str, str]:
    """Each host's `control { }` credentials with certificates made by the page's commands."""
    run_page_commands("control-certificates", directory, " ".join(f"{h}={a}" for h, a in HOSTS.items()))
    return {
        host: f'tls_ca: "{directory / "control-ca.pem"}" tls_certificate: "{directory / f"{host}.pem"}" '
        f'tls_private_key: "{directory / f"{host}.key"}"'
        for host in HOSTS
    }


class SplitRobot:
    """The two hosts' supervisors, started from `directory`; `credentials` maps host -> its `control` fields;
    `more_nodes`: the text of nodes the robot has beside its leader and follower."""

    def __init__(self, directory: Path, credentials: dict[str, str], env: dict, more_nodes: str = ""):
        self.directory = directory
        self.env = env
        self.more_nodes = more_nodes
        self.ports = {
            "discovery_port": free_port(socket.SOCK_DGRAM),
            "control_port": free_port(),
            "dashboard_port": free_port(),
        }
        self.control_dir = directory / "control"
        self.control_dir.mkdir(mode=0o700, parents=True, exist_ok=True)
        self.parts = {host: self._build(host, credentials[host]) for host in HOSTS}
        self.processes: dict[str, subprocess.Popen] = {}

    def _build(self, host: str, credentials: str) -> Path:
        source = self.directory / f"split_{host}.pbtxt"
        source.write_text(DESCRIPTION.format(credentials=credentials, more_nodes=self.more_nodes, **self.ports))
        out = self.directory / f"out_{host}"
        built = joshuac("build", source, "-o", out)
        assert built.returncode == 0, built.stderr
        return out / "hosts" / host

    @property
    def dashboard_url(self) -> str:
        return f"http://127.0.0.1:{self.ports['dashboard_port']}"

    def control_socket(self, host: str) -> Path:
        return self.control_dir / f"split.{host}.sock"

    def log(self, host: str) -> Path:
        return self.directory / f"{host}.log"

    def logs(self) -> str:
        return "\n".join(f"--- {host}\n{self.log(host).read_text()}" for host in self.processes)

    def start(self, host: str) -> None:
        with open(self.log(host), "a") as log:
            self.processes[host] = subprocess.Popen(
                [
                    sys.executable,
                    str(self.parts[host] / "supervisor.py"),
                    "--control-socket",
                    str(self.control_socket(host)),
                    "--log-dir",
                    str(self.directory / "logs" / host),
                ],
                stdout=log,
                stderr=subprocess.STDOUT,
                env=self.env,
            )

    def start_all(self) -> None:
        for host in HOSTS:
            self.start(host)
        self.wait_until(lambda: all(self.ready(host) for host in HOSTS), "every host ready")

    def ready(self, host: str) -> bool:
        return re.search(r"supervisor: ready: (\d+) of \1 nodes ready", self.log(host).read_text()) is not None

    def stop(self, host: str) -> int | None:
        process = self.processes.pop(host)
        process.send_signal(signal.SIGINT)
        try:
            return process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
            return None

    def stop_all(self) -> dict[str, int | None]:
        return {host: self.stop(host) for host in list(self.processes)}

    def ctl(self, host: str, *arguments: str) -> subprocess.CompletedProcess:
        """`supervisor.py ctl ARGUMENTS` run on `host`, against its control socket."""
        return subprocess.run(
            [
                sys.executable,
                str(self.parts[host] / "supervisor.py"),
                "ctl",
                "--control-socket",
                str(self.control_socket(host)),
                *arguments,
            ],
            capture_output=True,
            text=True,
            env=self.env,
            timeout=CTL_TIMEOUT_S,
        )

    def status(self, host: str, *arguments: str) -> dict:
        done = self.ctl(host, *arguments, "status", "--json")
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout)

    def all_hosts(self, host: str) -> dict:
        done = self.ctl(host, "status", "--all-hosts", "--json")
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout)

    def token(self) -> str:
        """The access token of the dashboard (on host gpu, beside its control socket)."""
        return token_path(self.control_socket("gpu")).read_text().strip()

    def api(self, path: str, method: str = "GET"):
        """The dashboard's JSON answer to `method path`, with the owner's token."""
        request = urllib.request.Request(
            self.dashboard_url + path, method=method, headers={"Authorization": f"Bearer {self.token()}"}
        )
        with urllib.request.urlopen(request, timeout=HTTP_TIMEOUT_S) as response:
            return json.loads(response.read())

    def wait_for_dashboard(self) -> None:
        def answers() -> bool:
            try:
                return bool(self.api("/api/robot"))
            except OSError:
                return False

        self.wait_until(answers, "the dashboard's answer")

    def node(self, host: str, name: str, *arguments: str) -> dict:
        return next(node for node in self.status(host, *arguments)["nodes"] if node["name"] == name)

    def wait_until(self, predicate, what: str, timeout_s: float = START_TIMEOUT_S):
        """The first true value of `predicate()`, polled; fails with the hosts' logs after `timeout_s`."""
        deadline = time.monotonic() + timeout_s
        while True:
            ended = {host: p.returncode for host, p in self.processes.items() if p.poll() is not None}
            assert not ended, f"supervisors ended {ended} while waiting for {what}:\n{self.logs()}"
            value = predicate()
            if value:
                return value
            assert time.monotonic() < deadline, f"no {what} within {timeout_s:g} s:\n{self.logs()}"
            time.sleep(POLL_S)


@contextlib.contextmanager
def running_split_robot(directory: Path, seed: str, credentials_of=None, more_nodes: str = "") -> Iterator[SplitRobot]:
    """The robot started in a ROS domain no other test holds meanwhile (claimed by `seed`, the test's id), with the
    hosts' credentials of `credentials_of(directory)` (default: passwords), until its dashboard answers and each
    host has heard the other; at exit stopped, each host's supervisor having to end 0."""
    credentials = (credentials_of or password_credentials)(directory / "credentials")
    with claimed_domain(seed) as domain:
        env = dict(
            os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", PYTHONUNBUFFERED="1"
        )
        robot = SplitRobot(directory, credentials, env, more_nodes)
        try:
            robot.start_all()
            robot.wait_for_dashboard()
            robot.wait_until(lambda: all(h["reachable"] for h in robot.api("/api/status")["hosts"]), "both hosts heard")
            yield robot
        finally:
            codes = robot.stop_all()
            assert codes == {"arm": 0, "gpu": 0}, robot.logs()
