"""The dashboard server without a browser: routes, token, same-origin writes, bounded client queues, CLI errors."""

import asyncio
import os
import subprocess
import sys
from pathlib import Path

import pytest
from api_contract import checking_replies
from dashboard_support import free_port, node_pid, running_robot
from starlette.testclient import TestClient

from joshua_core.dashboard import is_loopback
from joshua_runtime.dashboard.app import Dashboard
from joshua_runtime.dashboard.broadcaster import Broadcaster, Mailbox
from joshua_runtime.dashboard.control_client import ControlClient
from joshua_runtime.dashboard.robot_view import load_robot_view
from joshua_runtime.dashboard.security import HostAllowList, required_token

pytestmark = pytest.mark.process  # a generated supervisor and the dashboard command

ROOT = Path(__file__).resolve().parents[3]
MOCK_ARM = ROOT / "generated" / "mock_arm" / "manifest.json"
TOKEN = "s3cret-token-of-the-owner"
AUTHORIZED = {"Authorization": f"Bearer {TOKEN}"}


SLEEPERS = """robot_config { name: "sleepers" mode: MODE_TELEOPERATION
  node { name: "leader" type: CUSTOM executable: "/bin/sleep" args: ["600"] }
  node { name: "camera" type: CUSTOM executable: "/bin/sleep" args: ["600"] }
}
"""


@pytest.fixture
def supervised(tmp_path):
    """The control socket of a generated supervisor.py running two (non-ROS) processes."""
    with running_robot(SLEEPERS, tmp_path, dict(os.environ)) as control_socket:
        yield control_socket


def client_for(control_socket, tmp_path, authorized=True) -> TestClient:
    """A client of a dashboard on 127.0.0.1; it sends the owner's token unless `authorized` is False."""
    dashboard = Dashboard(
        load_robot_view(MOCK_ARM),
        ControlClient(control_socket),
        Broadcaster(),
        telemetry=None,
        web_dir=tmp_path / "no-page",
        token=TOKEN,
        allowed=HostAllowList("127.0.0.1"),
    )
    return checking_replies(
        TestClient(dashboard.app, base_url="http://127.0.0.1", headers=AUTHORIZED if authorized else None)
    )


def test_status_is_the_supervisor_status(supervised, tmp_path):
    with client_for(supervised, tmp_path) as client:
        status = client.get("/api/status").json()
    assert status["robot"] == "sleepers"
    assert [(n["name"], n["state"], n["pid"]) for n in status["nodes"]] == [
        ("leader", "running", node_pid(supervised, "leader")),
        ("camera", "running", node_pid(supervised, "camera")),
    ]


def test_restart_replaces_the_process_and_get_changes_nothing(supervised, tmp_path):
    old = node_pid(supervised, "leader")
    with client_for(supervised, tmp_path) as client:
        assert client.get("/api/nodes/leader/restart").status_code == 405
        assert node_pid(supervised, "leader") == old
        reply = client.post("/api/nodes/leader/restart").json()
    assert reply["node"] == "leader" and reply["state"] == "running"
    assert reply["pid"] == node_pid(supervised, "leader") != old


def test_errors_are_one_line_json(supervised, tmp_path):
    with client_for(supervised, tmp_path) as client:
        unknown = client.post("/api/nodes/nobody/restart")
        bad_action = client.post("/api/nodes/leader/explode")
    assert unknown.status_code == 404 and unknown.json() == {"error": "no node named 'nobody'", "kind": "not_found"}
    assert bad_action.status_code == 404 and "unknown action" in bad_action.json()["error"]


def test_unreachable_supervisor_answers_503(tmp_path):
    dashboard = Dashboard(
        load_robot_view(MOCK_ARM),
        ControlClient(tmp_path / "missing.sock"),
        Broadcaster(),
        telemetry=None,
        web_dir=tmp_path,
        token=TOKEN,
        allowed=HostAllowList("127.0.0.1"),
    )
    with checking_replies(TestClient(dashboard.app, base_url="http://127.0.0.1", headers=AUTHORIZED)) as client:
        reply = client.get("/api/status")
    assert reply.status_code == 503
    assert "missing.sock" in reply.json()["error"]


def test_without_the_token_every_api_route_answers_401_and_nothing_runs(supervised, tmp_path):
    old = node_pid(supervised, "leader")
    with client_for(supervised, tmp_path, authorized=False) as client:
        for method, path in [
            ("GET", "/api/status"),
            ("GET", "/api/robot"),
            ("GET", "/api/events"),
            ("GET", "/api/nodes/leader/logs"),
            ("POST", "/api/nodes/leader/restart"),
            ("POST", "/api/nodes/leader/stop"),
            ("POST", "/api/recorders/r/episode/start"),
        ]:
            assert client.request(method, path).status_code == 401, path
            wrong = client.request(method, path, headers={"Authorization": "Bearer wrong"})
            assert wrong.status_code == 401, path
        assert node_pid(supervised, "leader") == old
        authorized = client.get("/api/status", headers=AUTHORIZED)
        assert authorized.status_code == 200
        assert client.get("/").status_code == 503  # the page itself needs no token (here: not built)


def test_a_page_of_another_origin_cannot_post(supervised, tmp_path):
    old = node_pid(supervised, "leader")
    with client_for(supervised, tmp_path) as client:
        reply = client.post("/api/nodes/leader/stop", headers={"Origin": "http://evil.example"})
    assert reply.status_code == 403
    assert node_pid(supervised, "leader") == old


def test_the_fleet_view_requires_a_token_beyond_loopback_only():
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.20")
    assert required_token("127.0.0.1", None) == (None, False)
    assert required_token("127.0.0.1", "given") == ("given", False)
    token, generated = required_token("0.0.0.0", None)
    assert generated and len(token) >= 32


def test_a_stalled_client_holds_one_event_per_stream():
    mailbox = Mailbox()

    async def flood():
        for frame in range(10_000):
            for key in ("image:/camera", "joints:/leader", "status"):
                mailbox.put(key, f"{key}:{frame}".encode())

    asyncio.run(flood())
    assert len(mailbox._pending) == 3
    assert mailbox.dropped == 3 * 9_999
    assert asyncio.run(mailbox.get()) == b"image:/camera:9999"


def test_robot_view_reads_topology_and_streams():
    view = load_robot_view(MOCK_ARM)
    kinds = {s.topic: s.kind for s in view.streams}
    assert kinds == {
        "/camera/image_raw": "image",
        "/follower/joint_states": "joints",
        "/leader/joint_states": "joints",
        "/scan": "scan",
    }
    assert {"from": "leader", "to": "/leader/joint_states"} in view.topology["edges"]


def run_cli(*args) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "joshua_runtime.dashboard", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def test_cli_reports_a_bad_manifest_in_one_line(tmp_path):
    (tmp_path / "manifest.json").write_text("{not json")
    result = run_cli("--manifest", str(tmp_path / "manifest.json"))
    assert result.returncode == 2
    assert result.stderr.startswith("dashboard: error: ") and result.stderr.count("\n") == 1
    missing = run_cli("--manifest", str(tmp_path / "nothing.json"))
    assert missing.returncode == 2 and "cannot read manifest" in missing.stderr


def test_cli_reports_a_taken_port_and_a_bad_endpoint(tmp_path):
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", free_port()))
        taken.listen(1)
        result = run_cli("--manifest", str(MOCK_ARM), "--port", str(taken.getsockname()[1]))
    assert result.returncode == 1 and "cannot listen on 127.0.0.1" in result.stderr
    bad = run_cli("--manifest", str(MOCK_ARM), "--zenoh-connect", "127.0.0.1:7447")
    assert bad.returncode == 2 and "is not PROTOCOL/HOST:PORT" in bad.stderr


def test_cli_refuses_a_token_file_others_may_read_in_one_line(tmp_path):
    token_file = tmp_path / "robot.dashboard-token"
    token_file.write_text("a-token-everyone-can-read-0123")
    token_file.chmod(0o644)
    result = run_cli("--manifest", str(MOCK_ARM), "--port", "0", "--token-file", str(token_file))
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert result.stderr.startswith(f"dashboard: error: the dashboard token file {token_file} must be a file of user")
