"""The dashboard is its owner's alone, on loopback too: another local user, a page of another site (DNS
rebinding) and clients that hold connections open get nothing, and the token never leaks.

Each test runs a real robot: its generated supervisor.py (or `joshuac run`) with the dashboard process.
"""

import http.client
import json
import os
import re
import resource
import shutil
import socket
import stat
import subprocess
import sys
import tempfile
import time
import urllib.request
from contextlib import ExitStack
from pathlib import Path

import pytest
from dashboard_support import dashboard_token, free_port, get_json, node_pid, running_robot, stop, wait_for_server

from joshua_core.dashboard_token import token_path
from testsupport.joshuac_cli import joshuac

NOBODY = 65534
SYSTEM_PYTHON = "/usr/bin/python3"  # the other user's interpreter: it may not read this checkout's .venv
REQUEST_TIMEOUT_S = 30.0
URL_TIMEOUT_S = 120.0  # until `joshuac run` printed the address (it builds first)
# A user session's or a systemd service's usual soft limit on open files (systemd's DefaultLimitNOFILE).
USER_DEFAULT_NOFILE = 1024
IDLE_CONNECTIONS = 3000  # half of them send part of a request head, half nothing at all
ATTACK_HOLD_S = 25.0  # longer than the server's head deadline (10 s), with room for a busy machine
CLOSED_POLL_S = 0.5  # how often the idle connections are looked at until the server has closed them all
MAX_OUTPUT_GROWTH_BYTES = 16 * 1024
TOKEN_IN_ADDRESS = re.compile(r"#token=([A-Za-z0-9._~-]+)")


def robot_description(port: int, dashboard_extra: str = "") -> str:
    return f"""robot_config {{ name: "guarded" mode: MODE_TELEOPERATION
  node {{ name: "leader" type: CUSTOM executable: "/bin/sleep" args: ["600"] }}
  dashboard {{ port: {port} {dashboard_extra} }}
}}
"""


@pytest.fixture
def world_readable_directory():
    """A directory every user may enter (pytest's own are root's only), so that only the dashboard's own
    permissions keep another user from its files."""
    directory = Path(tempfile.mkdtemp(prefix="joshua-dashboard-test-"))
    directory.chmod(0o755)
    yield directory
    shutil.rmtree(directory, ignore_errors=True)


def request(port: int, method: str, path: str, headers: dict) -> tuple[int, str]:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=REQUEST_TIMEOUT_S)
    try:
        connection.request(method, path, headers=headers)
        response = connection.getresponse()
        return response.status, response.read().decode(errors="replace")
    finally:
        connection.close()


def as_nobody() -> None:
    os.setgroups([])
    os.setresgid(NOBODY, NOBODY, NOBODY)
    os.setresuid(NOBODY, NOBODY, NOBODY)


OTHER_USER = """
import json, sys, urllib.error, urllib.request
url, token_file = sys.argv[1:]
result = {"uid": __import__("os").getuid()}
try:
    urllib.request.urlopen(urllib.request.Request(url + "/api/nodes/leader/stop", method="POST"), timeout=30)
    result["stop"] = 200
except urllib.error.HTTPError as exc:
    result["stop"] = exc.code
try:
    result["token"] = open(token_file).read()
except OSError as exc:
    result["token_error"] = exc.errno
print(json.dumps(result))
"""


def test_another_local_user_can_neither_stop_a_node_nor_read_the_token(world_readable_directory, ros_env):
    port = free_port()
    with running_robot(robot_description(port), world_readable_directory, ros_env, port) as control_socket:
        leader = node_pid(control_socket, "leader")
        token_file = token_path(control_socket)
        other = subprocess.run(
            [SYSTEM_PYTHON, "-I", "-c", OTHER_USER, f"http://127.0.0.1:{port}", str(token_file)],
            preexec_fn=as_nobody,  # noqa: PLW1509
            cwd="/",
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        assert other.returncode == 0, other.stderr
        result = json.loads(other.stdout)
        assert result["uid"] == NOBODY
        assert result["stop"] == 401
        assert node_pid(control_socket, "leader") == leader
        assert "token" not in result and result["token_error"] == 13  # EACCES
        assert stat.S_IMODE(token_file.stat().st_mode) == 0o600
        assert stat.S_IMODE(token_file.parent.stat().st_mode) == 0o700
        # The owner, with the token, may.
        stopped = request(
            port, "POST", "/api/nodes/leader/stop", {"Authorization": f"Bearer {token_file.read_text().strip()}"}
        )
        assert stopped[0] == 200 and node_pid(control_socket, "leader") is None


def test_a_foreign_host_is_refused_even_with_the_token_and_a_matching_origin(tmp_path, ros_env):
    port = free_port()
    description = robot_description(port, 'allowed_host: "robot.example.org"')
    with running_robot(description, tmp_path, ros_env, port) as control_socket:
        leader = node_pid(control_socket, "leader")
        rebound = {"Host": f"evil.test:{port}", "Origin": f"http://evil.test:{port}"}
        status, body = request(port, "POST", "/api/nodes/leader/restart", rebound)
        assert status == 403 and "evil.test" in body
        assert node_pid(control_socket, "leader") == leader
        token = {"Authorization": f"Bearer {dashboard_token(control_socket)}"}
        assert request(port, "POST", "/api/nodes/leader/restart", {**rebound, **token})[0] == 403
        assert request(port, "GET", "/", {"Host": f"evil.test:{port}"})[0] == 403
        assert request(port, "GET", "/api/status", {"Host": f"evil.test:{port}", **token})[0] == 403
        assert node_pid(control_socket, "leader") == leader
        for host in ("127.0.0.1", "localhost", "robot.example.org", "LOCALHOST."):
            assert request(port, "GET", "/api/status", {"Host": f"{host}:{port}", **token})[0] == 200, host
        # A tunnel forwards another port of another machine's localhost: the port does not matter.
        assert request(port, "GET", "/api/status", {"Host": "localhost:9999", **token})[0] == 200


def process_texts(name: str) -> dict[int, bytes]:
    """/proc/PID/NAME (cmdline, environ) of every process that can be read."""
    texts = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                texts[int(entry.name)] = (entry / name).read_bytes()
            except OSError:
                pass
    return texts


def wait_for_address(runner: subprocess.Popen, stdout: Path) -> str:
    deadline = time.monotonic() + URL_TIMEOUT_S
    while time.monotonic() < deadline:
        match = TOKEN_IN_ADDRESS.search(stdout.read_text())
        if match:
            return match.group(1)
        assert runner.poll() is None, f"joshuac run exited with {runner.returncode}: {stdout.read_text()}"
        time.sleep(0.1)
    raise AssertionError(f"joshuac run printed no address with a token: {stdout.read_text()}")


def first_events(port: int, token: str, size: int = 4096) -> str:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=REQUEST_TIMEOUT_S)
    try:
        connection.request("GET", "/api/events", headers={"Authorization": f"Bearer {token}"})
        response = connection.getresponse()
        assert response.status == 200
        return response.read1(size).decode(errors="replace")
    finally:
        connection.close()


def test_joshuac_run_prints_the_token_once_and_nothing_else_shows_it(tmp_path, ros_env):
    port = free_port()
    source = tmp_path / "guarded.pbtxt"
    source.write_text(robot_description(port))
    stdout, stderr = tmp_path / "run.out", tmp_path / "run.err"
    with open(stdout, "w") as out, open(stderr, "w") as err:
        runner = subprocess.Popen(
            [sys.executable, "-m", "joshua_codegen", "run", str(source)], env=ros_env, stdout=out, stderr=err
        )
    try:
        token = wait_for_address(runner, stdout)
        base = f"http://127.0.0.1:{port}"
        wait_for_server(f"{base}/api/robot", runner, stderr)
        state_dir = Path(ros_env["XDG_STATE_HOME"])
        dashboard_log = state_dir / "joshua" / "guarded" / "logs" / "dashboard.log"
        deadline = time.monotonic() + URL_TIMEOUT_S
        while "dashboard of guarded" not in (dashboard_log.read_text() if dashboard_log.exists() else ""):
            assert time.monotonic() < deadline, "the dashboard logged no start line"
            time.sleep(0.1)
        answers = [
            json.dumps(get_json(f"{base}/api/{route}", token))
            for route in ("robot", "status", "nodes/dashboard/logs?lines=2000", "nodes/leader/logs")
        ]
        answers.append(request(port, "POST", "/api/nodes/leader/restart", {"Authorization": f"Bearer {token}"})[1])
        answers.append(first_events(port, token))
        assert "dashboard of guarded" in answers[2]  # the dashboard's own log, as served
        for answer in answers:
            assert token not in answer
        for kind in ("cmdline", "environ"):
            holders = [pid for pid, text in process_texts(kind).items() if token.encode() in text]
            assert not holders, f"the token is in /proc/{holders[0]}/{kind}"
        for root in (state_dir, Path(ros_env["XDG_RUNTIME_DIR"])):
            for path in root.rglob("*"):
                if path.is_file() and path != token_path(Path(ros_env["XDG_RUNTIME_DIR"]) / "joshua" / "guarded.sock"):
                    assert token.encode() not in path.read_bytes(), path
    finally:
        stop(runner)
    output = stdout.read_text() + stderr.read_text()
    assert output.count(token) == 1, output  # the address joshuac printed, on its own output only
    assert f"joshuac: dashboard of guarded: http://127.0.0.1:{port}/#token={token}" in stdout.read_text()


def test_joshuac_run_stops_with_one_line_when_others_may_write_to_the_token_directory(tmp_path, ros_env):
    shared = Path(ros_env["XDG_RUNTIME_DIR"]) / "joshua"
    shared.mkdir()
    shared.chmod(0o777)
    source = tmp_path / "guarded.pbtxt"
    source.write_text(robot_description(free_port()))
    result = joshuac("run", source, env=ros_env)
    assert result.returncode == 1 and result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith(
        f"joshuac: error: {shared} must be a directory of user {os.geteuid()} that no one else may write"
    )
    assert not (shared / "guarded.dashboard-token").exists()


def test_thousands_of_idle_connections_neither_stop_a_client_nor_flood_the_output(tmp_path, ros_env):
    port = free_port()
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    assert hard >= IDLE_CONNECTIONS + 200, f"this test needs {IDLE_CONNECTIONS + 200} open files; the limit is {hard}"
    with ExitStack() as stack:
        resource.setrlimit(resource.RLIMIT_NOFILE, (USER_DEFAULT_NOFILE, hard))  # inherited by the robot
        try:
            control_socket = stack.enter_context(running_robot(robot_description(port), tmp_path, ros_env, port))
        finally:
            resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, IDLE_CONNECTIONS + 200), hard))
        stack.callback(resource.setrlimit, resource.RLIMIT_NOFILE, (soft, hard))
        output = tmp_path / "supervisor.log"
        size_before = output.stat().st_size
        attackers = []
        stack.callback(lambda: [attacker.close() for attacker in attackers])
        for index in range(IDLE_CONNECTIONS):
            attacker = socket.socket()
            attacker.settimeout(5)
            attackers.append(attacker)
            try:
                attacker.connect(("127.0.0.1", port))
                if index % 2:
                    attacker.sendall(b"GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
            except OSError:
                pass  # refused or reset: the server had no room, as it may

        page = urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=REQUEST_TIMEOUT_S)
        assert page.status == 200 and b'<div id="root">' in page.read()
        token = dashboard_token(control_socket)
        status = get_json(f"http://127.0.0.1:{port}/api/status", token)
        assert [node["name"] for node in status["nodes"]] == ["leader", "dashboard"]

        deadline = time.monotonic() + ATTACK_HOLD_S
        still_open = [attacker for attacker in attackers if _open(attacker)]
        while still_open and time.monotonic() < deadline:
            time.sleep(CLOSED_POLL_S)
            still_open = [attacker for attacker in still_open if _open(attacker)]
        assert not still_open, f"{len(still_open)} of {IDLE_CONNECTIONS} idle connections were never closed"
        assert get_json(f"http://127.0.0.1:{port}/api/status", token)["robot"] == "guarded"
        growth = output.stat().st_size - size_before
        assert growth < MAX_OUTPUT_GROWTH_BYTES, output.read_text()[-3000:]


def _open(connection: socket.socket) -> bool:
    """Whether the server still holds this connection open (it neither closed nor reset it)."""
    try:
        return connection.recv(1, socket.MSG_DONTWAIT) != b""
    except BlockingIOError:
        return True
    except OSError:
        return False
