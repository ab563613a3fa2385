"""Who may reach a robot's control plane: real Zenoh sessions against the router of a running robot on two hosts
(passwords, or certificates, made by the commands of docs/across-computers.md). A peer without the robot's credentials controls
nothing; a host's credentials do not let it publish or answer as another host."""

import contextlib
import json
import time

import pytest

from joshua_core import control_plane
from joshua_runtime.dashboard.zenoh_link import open_session
from testsupport.split_robot import (
    ROUTER,
    SplitRobot,
    password_credentials,
    run_page_commands,
    running_split_robot,
    tls_credentials,
)

SETTLE_S = 1.5  # time for a session to link to the router and its declarations to reach it, were they allowed
QUERY_TIMEOUT_S = 3.0
FORGED_PID = 999_999


def endpoint(robot: SplitRobot, scheme: str = "tcp") -> str:
    return f"{scheme}/127.0.0.1:{robot.ports['control_port']}"


def peer(robot: SplitRobot, settings: dict, scheme: str = "tcp"):
    """A Zenoh peer that keeps trying the robot's router (it opens whether or not it is admitted)."""
    return open_session("peer", connect=[endpoint(robot, scheme)], settings=settings)


def ask(session, robot: SplitRobot, host: str, request: dict) -> list:
    key = control_plane.control_key("split", host)
    return [r for r in session.get(key, payload=json.dumps(request), timeout=QUERY_TIMEOUT_S) if r.ok is not None]


@pytest.fixture
def running(tmp_path, request):
    with contextlib.ExitStack() as stack:
        yield lambda credentials_of: stack.enter_context(
            running_split_robot(tmp_path, request.node.nodeid, credentials_of)
        )


def test_peers_without_the_robots_password_control_nothing(running, tmp_path):
    robot = running(password_credentials)
    users = (tmp_path / "credentials" / "control-users.txt").read_text()
    leader = robot.node("arm", "leader")
    sessions = {
        "anonymous": peer(robot, {}),
        "wrong password": peer(robot, {"transport/auth/usrpwd/user": "gpu", "transport/auth/usrpwd/password": "x"}),
        "unknown user": peer(robot, {"transport/auth/usrpwd/user": "intruder", "transport/auth/usrpwd/password": "x"}),
    }
    try:
        time.sleep(SETTLE_S)
        for who, session in sessions.items():
            assert list(session.info.routers_zid()) == [], f"{who} was admitted"
            for host in ("arm", "gpu"):
                assert ask(session, robot, host, {"command": "restart", "node": "leader"}) == [], (who, host)
    finally:
        for session in sessions.values():
            session.close()
    after = robot.node("arm", "leader")
    assert (after["pid"], after["manual_restarts"]) == (leader["pid"], leader["manual_restarts"])
    for host in ("arm", "gpu"):  # the build and the logs hold no password
        secrets = [line.partition(":")[2] for line in users.splitlines()]
        text = robot.log(host).read_text() + "".join(p.read_text() for p in robot.parts[host].rglob("*.py"))
        assert not any(secret in text for secret in secrets), host


def test_a_host_cannot_publish_or_answer_as_another(running, tmp_path):
    robot = running(password_credentials)
    password = (tmp_path / "credentials" / "gpu.control-password").read_text().strip()
    gpu = open_session(
        "client",
        connect=[endpoint(robot)],
        settings={"transport/auth/usrpwd/user": "gpu", "transport/auth/usrpwd/password": password},
    )
    answered = []
    try:
        forged = {"robot": "split", "host": ROUTER, "nodes": [dict(robot.node("arm", "leader"), pid=FORGED_PID)]}
        queryable = gpu.declare_queryable(
            control_plane.control_key("split", ROUTER), lambda query: answered.append(query) or query.drop()
        )
        time.sleep(SETTLE_S)
        deadline = time.monotonic() + 3 * SETTLE_S
        while time.monotonic() < deadline:
            gpu.put(control_plane.status_key("split", ROUTER), json.dumps(forged))
            shown = {n["name"]: n for n in robot.api("/api/status")["nodes"]}
            assert shown["leader"]["pid"] != FORGED_PID, shown["leader"]
            time.sleep(0.2)
        remote = robot.status("gpu", "--host", ROUTER)  # answered by arm's own agent, not the forged queryable
        assert {n["name"] for n in remote["nodes"]} == {"discovery_server", "leader", "host_agent_arm"}
        assert answered == []
        # what the host may do with its own credentials: ask every host, and hear every host's status
        assert [json.loads(r.ok.payload.to_bytes())["ok"] for r in ask(gpu, robot, ROUTER, {"command": "status"})] == [
            True
        ]
        queryable.undeclare()
    finally:
        gpu.close()


def test_mutual_tls_admits_only_certificates_of_the_robots_ca(running, tmp_path):
    robot = running(tls_credentials)
    certificates = tmp_path / "credentials"
    other = run_page_commands("control-certificates", tmp_path / "other", "gpu=127.0.0.2")
    tls = "transport/link/tls/"
    sessions = {
        "no certificate": peer(robot, {f"{tls}root_ca_certificate": str(certificates / "control-ca.pem")}, "tls"),
        "another CA's gpu": peer(
            robot,
            {
                f"{tls}root_ca_certificate": str(certificates / "control-ca.pem"),
                f"{tls}connect_certificate": str(other / "gpu.pem"),
                f"{tls}connect_private_key": str(other / "gpu.key"),
                f"{tls}enable_mtls": True,
            },
            "tls",
        ),
    }
    try:
        time.sleep(SETTLE_S)
        for who, session in sessions.items():
            assert list(session.info.routers_zid()) == [], f"{who} was admitted"
            assert ask(session, robot, ROUTER, {"command": "stop", "node": "leader"}) == [], who
    finally:
        for session in sessions.values():
            session.close()
    leader = robot.node("arm", "leader")
    assert leader["state"] == "running"
    restarted = robot.api("/api/nodes/leader/restart", method="POST")  # the robot's own hosts do, over TLS
    assert restarted["pid"] == robot.node("arm", "leader")["pid"] != leader["pid"]
