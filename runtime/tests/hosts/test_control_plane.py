"""The control plane of a robot on two hosts, each host's part run by its generated supervisor.py on this machine
(hosts 127.0.0.1 and 127.0.0.2), joined by the hosts' agents over Zenoh with passwords made by the commands of
docs/across-computers.md: the dashboard on one host shows and controls the processes of both, `ctl` reaches the other host,
a stopped Discovery Server and a silent host are reported as such.

One robot serves the tests of this module, in order; each test leaves it as it found it.
"""

import pytest

from testsupport.split_robot import running_split_robot

SERVER_WATCH_TIMEOUT_S = 20.0  # the agent's bound is 5 s; this only ends a test that would hang
NODE_FIELDS = {"name", "state", "pid", "restarts", "manual_restarts", "ready", "since_s", "host"}


@pytest.fixture(scope="module")
def robot(tmp_path_factory, request):
    with running_split_robot(tmp_path_factory.mktemp("split"), request.node.nodeid) as robot:
        yield robot


def by_name(status: dict) -> dict[str, dict]:
    return {node["name"]: node for node in status["nodes"]}


def test_the_dashboard_on_one_host_shows_and_restarts_a_node_of_the_other(robot):
    status = robot.api("/api/status")
    nodes = by_name(status)
    assert {name: node["host"] for name, node in nodes.items()} == {
        "discovery_server": "arm",
        "leader": "arm",
        "host_agent_arm": "arm",
        "follower": "gpu",
        "dashboard": "gpu",
        "host_agent_gpu": "gpu",
    }
    assert all(set(node) == NODE_FIELDS for node in status["nodes"]), status["nodes"]
    assert all(node["state"] == "running" for node in status["nodes"]), status["nodes"]
    assert [(h["name"], h["address"], h["reachable"]) for h in status["hosts"]] == [
        ("arm", "127.0.0.1", True),
        ("gpu", "127.0.0.2", True),
    ]
    before = robot.node("arm", "leader")
    assert nodes["leader"]["pid"] == before["pid"]

    reply = robot.api("/api/nodes/leader/restart", method="POST")

    after = robot.node("arm", "leader")
    assert reply["node"] == "leader" and reply["pid"] == after["pid"] != before["pid"], (reply, before, after)
    assert after["manual_restarts"] == before["manual_restarts"] + 1
    assert robot.api("/api/nodes/leader/logs?lines=5")["lines"], "the leader's log, from its host"


def test_ctl_on_one_host_controls_the_other_through_its_agent(robot):
    remote = robot.status("gpu", "--host", "arm")
    local = robot.status("arm")
    assert remote["host"] == "arm" and remote["run"] == local["run"]
    assert {n["name"]: n["pid"] for n in remote["nodes"]} == {n["name"]: n["pid"] for n in local["nodes"]}

    stopped = robot.ctl("gpu", "--host", "arm", "stop", "leader")
    assert stopped.returncode == 0 and stopped.stdout.strip() == "leader: stopped", stopped
    assert robot.node("arm", "leader")["state"] == "stopped"
    again = robot.ctl("gpu", "--host", "arm", "stop", "leader")
    assert again.returncode == 1 and "leader is already stopped" in again.stderr, again  # the supervisor's refusal
    started = robot.ctl("gpu", "--host", "arm", "start", "leader")
    assert started.returncode == 0 and robot.node("arm", "leader")["state"] == "running", started

    table = robot.ctl("arm", "status", "--all-hosts")
    assert table.returncode == 0, table.stderr
    assert "host arm" in table.stdout and "host gpu" in table.stdout
    rows = {tuple(line.split()[:2]) for line in table.stdout.splitlines() if not line.startswith("host ")}
    assert {("arm", "leader"), ("gpu", "follower"), ("gpu", "dashboard")} <= rows, table.stdout
    logs = robot.ctl("arm", "--host", "gpu", "logs", "follower", "-n", "3")
    assert logs.returncode == 0 and logs.stdout.strip(), logs


def test_ctl_refuses_host_options_it_cannot_serve(robot):
    unknown = robot.ctl("gpu", "--host", "nowhere", "status")
    assert unknown.returncode == 2 and "has no host 'nowhere' (hosts: arm, gpu)" in unknown.stderr, unknown
    follow = robot.ctl("gpu", "--host", "arm", "logs", "leader", "-f")
    assert follow.returncode == 2 and "logs -f follows a node of this host only" in follow.stderr, follow
    reload = robot.ctl("gpu", "--host", "arm", "reload", str(robot.parts["arm"]))
    assert reload.returncode == 2 and "reload applies a build on the host it runs on" in reload.stderr, reload


def test_a_stopped_discovery_server_is_reported_unreachable_then_reachable_again(robot):
    assert robot.status("gpu")["discovery"]["reachable"] is True
    assert robot.ctl("arm", "stop", "discovery_server").returncode == 0

    discovery = robot.wait_until(
        lambda: (d := robot.status("gpu")["discovery"])["reachable"] is False and d,
        "the Discovery Server reported unreachable",
        SERVER_WATCH_TIMEOUT_S,
    )
    assert discovery["server"] == f"127.0.0.1:{robot.ports['discovery_port']}"
    assert "nodes on this host cannot discover the others" in discovery["detail"]
    assert f"discovery server 127.0.0.1:{robot.ports['discovery_port']} unreachable" in robot.log("gpu").read_text()
    robot.wait_until(  # the dashboard's view of both hosts, a status period later
        lambda: [h["discovery"]["reachable"] for h in robot.api("/api/status")["hosts"]] == [False, False],
        "both hosts' reports on the dashboard",
    )

    assert robot.ctl("arm", "start", "discovery_server").returncode == 0
    robot.wait_until(
        lambda: robot.status("gpu")["discovery"]["reachable"] is True,
        "the Discovery Server reachable again",
        SERVER_WATCH_TIMEOUT_S,
    )
    assert "answers again after" in robot.status("gpu")["discovery"]["detail"]


def test_the_processes_of_a_host_whose_agent_is_gone_are_shown_unknown_never_running(robot):
    assert robot.ctl("arm", "stop", "host_agent_arm").returncode == 0

    status = robot.wait_until(
        lambda: (s := robot.api("/api/status"))["hosts"][0]["reachable"] is False and s, "host arm unreachable"
    )
    nodes = by_name(status)
    for name in ("discovery_server", "leader", "host_agent_arm"):
        assert (nodes[name]["state"], nodes[name]["pid"], nodes[name]["ready"]) == ("unknown", None, False), nodes
    # the follower reads /leader/joint_states, published on arm only
    assert nodes["follower"]["state"] == "waiting" and nodes["follower"]["waiting_for"] == ["arm"], nodes
    assert nodes["dashboard"]["state"] == "running"
    assert "not heard from for" in status["hosts"][0]["detail"]
    silent = robot.ctl("gpu", "--host", "arm", "status")
    assert silent.returncode == 3 and "host arm did not answer" in silent.stderr, silent

    assert robot.ctl("arm", "start", "host_agent_arm").returncode == 0

    def all_running():
        status = robot.api("/api/status")
        return all(node["state"] == "running" for node in status["nodes"]) and status

    status = robot.wait_until(all_running, "every process running again")
    assert "waiting_for" not in by_name(status)["follower"]
