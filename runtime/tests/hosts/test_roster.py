"""What the agent makes of the hosts' statuses (roster.py) and of the requests it is given (requests.py)."""

import json

import pytest

from joshua_runtime.hosts.requests import (
    RELAY_MARGIN_S,
    REQUEST_LIMIT_BYTES,
    WAIT_MAX_S,
    RequestRefused,
    parse,
    parse_remote,
)
from joshua_runtime.hosts.roster import HOST_SILENT_AFTER_S, Placement, Roster

MANIFEST = {
    "robot": {"name": "split"},
    "host": "gpu",
    "hosts": [
        {"name": "arm", "address": "10.0.0.2", "processes": ["leader", "camera", "host_agent_arm"]},
        {"name": "gpu", "address": "10.0.0.3", "processes": ["follower", "viewer", "host_agent_gpu"]},
    ],
    "topics": [
        {"name": "/leader/joint_states", "publishers": [{"node": "leader"}], "subscribers": [{"node": "follower"}]},
        {"name": "/image", "publishers": [{"node": "camera"}, {"node": "viewer"}], "subscribers": [{"node": "viewer"}]},
    ],
}


def node(name: str, state: str = "running", pid: int | None = 10) -> dict:
    return {
        "name": name,
        "state": state,
        "pid": pid,
        "restarts": 2,
        "manual_restarts": 1,
        "ready": True,
        "since_s": 5.0,
    }


def status(host: str) -> dict:
    plan = next(h for h in MANIFEST["hosts"] if h["name"] == host)
    return {"robot": "split", "host": host, "run": {"id": host}, "nodes": [node(name) for name in plan["processes"]]}


@pytest.fixture
def roster() -> Roster:
    return Roster(Placement.from_manifest(MANIFEST), linked=True)


def test_every_process_of_every_heard_host_is_listed_with_its_host(roster):
    assert roster.record("arm", status("arm"), 100.0) and roster.record("gpu", status("gpu"), 100.5)
    robot = roster.aggregate(101.0)
    assert [(n["host"], n["name"], n["state"]) for n in robot["nodes"]] == [
        ("arm", "leader", "running"),
        ("arm", "camera", "running"),
        ("arm", "host_agent_arm", "running"),
        ("gpu", "follower", "running"),
        ("gpu", "viewer", "running"),
        ("gpu", "host_agent_gpu", "running"),
    ]
    assert [(h["name"], h["reachable"], h["run"]) for h in robot["hosts"]] == [
        ("arm", True, {"id": "arm"}),
        ("gpu", True, {"id": "gpu"}),
    ]


def test_a_silent_hosts_processes_are_unknown_and_their_readers_wait(roster):
    roster.record("arm", status("arm"), 100.0)
    roster.record("gpu", status("gpu"), 100.0 + HOST_SILENT_AFTER_S)
    robot = roster.aggregate(100.0 + HOST_SILENT_AFTER_S + 0.5)
    nodes = {n["name"]: n for n in robot["nodes"]}
    assert nodes["leader"] | {"since_s": None} == {
        "name": "leader",
        "state": "unknown",
        "pid": None,
        "restarts": 2,
        "manual_restarts": 1,
        "ready": False,
        "since_s": None,
        "host": "arm",
    }
    assert nodes["leader"]["since_s"] == pytest.approx(HOST_SILENT_AFTER_S + 0.5)
    assert (nodes["follower"]["state"], nodes["follower"]["waiting_for"]) == ("waiting", ["arm"])
    assert nodes["viewer"]["state"] == "running" and "waiting_for" not in nodes["viewer"]  # it publishes /image too
    assert robot["hosts"][0]["reachable"] is False and robot["hosts"][0]["detail"].startswith("not heard from for")


def test_a_host_never_heard_from_and_one_without_a_control_plane_say_why():
    roster = Roster(Placement.from_manifest(MANIFEST), linked=False)
    roster.record("gpu", status("gpu"), 1.0)
    hosts = roster.aggregate(1.5)["hosts"]
    assert hosts[0]["detail"] == "no control plane: the description has no `control { }` block"
    linked = Roster(Placement.from_manifest(MANIFEST), linked=True)
    assert linked.aggregate(1.0)["hosts"][0]["detail"] == "not heard from yet"


@pytest.mark.parametrize(
    "forged",
    [
        {"nodes": [node("follower")]},  # a process of another host
        {"nodes": [node("leader") | {"pid": "1"}]},
        {"nodes": [node("leader") | {"since_s": float("nan")}]},
        {"nodes": [node("leader") | {"state": "x" * 100}]},
        {"nodes": "leader"},
        ["leader"],
    ],
)
def test_a_status_that_is_not_one_of_that_hosts_supervisor_is_dropped(roster, forged):
    assert not roster.record("arm", forged, 1.0)
    assert roster.aggregate(1.0)["hosts"][0]["reachable"] is False


def test_requests_name_a_host_of_the_robot_and_follow_no_log():
    hosts = ("arm", "gpu")
    assert parse(b'{"command": "status"}', "gpu", hosts).host == "gpu"
    request = parse(b'{"command": "restart", "node": "leader", "host": "arm"}', "gpu", hosts)
    assert (request.host, request.forwarded) == ("arm", {"command": "restart", "node": "leader"})
    assert parse(b'{"command": "status", "all_hosts": true}', "gpu", hosts).all_hosts
    refused = [
        (b'{"command": "status", "host": "laptop"}', "not_found"),
        (b'{"command": "stop", "node": "x", "all_hosts": true}', "bad_request"),
        (b'{"command": "logs", "node": "x", "follow": true, "host": "arm"}', "bad_request"),
        (b"[" * 10 + b"]" * 10, "bad_request"),
        (json.dumps({"command": "status", "pad": "x" * REQUEST_LIMIT_BYTES}).encode(), "bad_request"),
        (b"\xff", "bad_request"),
        (b'{"command": "reload", "path": "/tmp/out", "host": "arm"}', "bad_request"),  # a build of another host
    ]
    for line, kind in refused:
        with pytest.raises(RequestRefused) as refusal:
            parse(line, "gpu", hosts)
        assert refusal.value.kind == kind, line
    for payload in (b'{"command": "status", "host": "arm"}', b'{"command": "reload", "path": "/opt/joshua/evil"}'):
        with pytest.raises(RequestRefused):
            parse_remote(payload, "arm")


def test_a_request_says_how_long_its_sender_waits_and_each_hop_waits_a_margin_less():
    hosts = ("arm", "gpu")
    request = parse(b'{"command": "stop", "node": "saver", "host": "arm", "wait_s": 150}', "gpu", hosts)
    assert (request.forwarded, request.wait_s) == ({"command": "stop", "node": "saver"}, 150.0)
    assert request.relayed_wait_s() == 150.0 - RELAY_MARGIN_S
    remote = parse_remote(json.dumps(request.remote()).encode(), "arm")
    assert (remote.host, remote.forwarded) == ("arm", {"command": "stop", "node": "saver"})
    assert remote.relayed_wait_s() == 150.0 - 2 * RELAY_MARGIN_S  # what the supervisor there is given
    unsaid = parse(b'{"command": "stop", "node": "saver", "host": "arm"}', "gpu", hosts)
    assert unsaid.relayed_wait_s() is None and unsaid.remote() == unsaid.forwarded  # the agents' own bounds
    for wait in ("0", "-1", "true", '"150"', str(WAIT_MAX_S + 1), "1e999"):
        with pytest.raises(RequestRefused) as refusal:
            parse(f'{{"command": "stop", "node": "saver", "wait_s": {wait}}}'.encode(), "gpu", hosts)
        assert refusal.value.kind == "bad_request", wait
