"""The fleet's schema for statuses read from zenoh, and its roster's bounds, without a network."""

import json

import pytest

from joshua_runtime.dashboard.fleet_roster import MAX_ROBOTS, PRUNE_PERIOD_S, Roster
from joshua_runtime.dashboard.fleet_status import MAX_NODES, StatusRejected, read_status

SUPERVISOR_STATUS = {
    "robot": "arm",
    "nodes": [
        {"name": "leader", "state": "running", "pid": 4242, "restarts": 1, "ready": True, "since_s": 12.5},
        {"name": "camera", "state": "stopped", "pid": None, "restarts": 0, "ready": False, "since_s": 3},
    ],
    "url": "https://arm.example:8640/",
}


class Clock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def test_the_supervisors_status_with_the_dashboards_url_fits_the_schema():
    status = read_status("arm", json.dumps(SUPERVISOR_STATUS).encode())
    assert [(node.name, node.state, node.pid) for node in status.nodes] == [
        ("leader", "running", 4242),
        ("camera", "stopped", None),
    ]
    assert status.url == "https://arm.example:8640/"
    assert read_status("arm", b'{"error": "supervisor unreachable"}').nodes == []


@pytest.mark.parametrize(
    ("payload", "reason"),
    [
        ([1, 2, 3], "Input should be an object"),
        ({"nodes": "abc"}, "nodes: Input should be a valid array"),
        ({"nodes": [{"name": "n", "state": "running", "pid": "7"}]}, "nodes.0.pid: Input should be a valid integer"),
        ({"url": "javascript:alert(1)"}, "url: Value error, the address is not http:// or https:// with a host"),
        ({"url": "JaVaScRiPt:alert(1)"}, "url: Value error, the address is not http:// or https:// with a host"),
        ({"url": "java\tscript:alert(1)"}, "url: Value error, the address holds a space or control character"),
        ({"url": "//evil.example/"}, "url: Value error, the address is not http:// or https:// with a host"),
        ({"url": "http://[::1/"}, "url: Value error, the address cannot be read"),
        ({"robot": "other"}, "it names another robot"),
        ({"nodes": [{"name": f"n{i}", "state": "running"} for i in range(MAX_NODES + 1)]}, "nodes: List should have"),
    ],
)
def test_a_status_outside_the_schema_is_rejected_with_where_and_why_but_not_what(payload, reason):
    with pytest.raises(StatusRejected) as rejected:
        read_status("arm", json.dumps(payload).encode())
    assert str(rejected.value).startswith(reason)
    assert "alert" not in str(rejected.value)


def test_a_key_that_names_no_robot_is_rejected():
    with pytest.raises(StatusRejected, match="does not name a robot"):
        read_status("Not-A-Robot", json.dumps(SUPERVISOR_STATUS).encode())


def test_a_silent_robot_goes_offline_then_away():
    clock = Clock()
    roster = Roster(offline_after_s=10, forget_after_s=60, clock=clock)
    roster.update("arm", read_status("arm", json.dumps(SUPERVISOR_STATUS).encode()))
    clock.now += 10
    assert [(r["name"], r["online"], r["last_seen_s"]) for r in roster.robots()] == [("arm", True, 10.0)]
    clock.now += 0.5
    assert [r["online"] for r in roster.robots()] == [False]
    clock.now += 50
    assert roster.robots() == []


def test_a_withdrawn_robot_is_offline_with_its_last_status_until_it_publishes_again():
    clock = Clock()
    roster = Roster(offline_after_s=10, forget_after_s=60, clock=clock)
    roster.update("arm", read_status("arm", json.dumps(SUPERVISOR_STATUS).encode()))
    roster.withdraw("arm")
    roster.withdraw("never_heard_of")
    [entry] = roster.robots()
    assert (entry["name"], entry["online"], entry["last_seen_s"]) == ("arm", False, 0.0)
    assert [node["name"] for node in entry["nodes"]] == ["leader", "camera"]
    clock.now += 1
    roster.update("arm", read_status("arm", json.dumps(SUPERVISOR_STATUS).encode()))
    assert [(r["online"], r["last_seen_s"]) for r in roster.robots()] == [(True, 0.0)]
    roster.withdraw("arm")
    clock.now += 60.5
    assert roster.robots() == []


def test_a_full_roster_turns_new_robots_away_until_a_silent_one_is_forgotten():
    clock = Clock()
    roster = Roster(offline_after_s=10, forget_after_s=60, clock=clock)
    status = read_status("arm", b'{"nodes": []}')
    for index in range(MAX_ROBOTS):
        assert roster.update(f"robot_{index}", status)
        clock.now += 0.01
    assert not roster.update("newcomer", status)
    assert roster.update("robot_5", status)  # known robots keep updating
    clock.now = 1000.0 + 60 + PRUNE_PERIOD_S  # the first ones fall silent long enough to be forgotten
    assert roster.update("newcomer", status)
    assert len(roster) <= MAX_ROBOTS
    assert "robot_0" not in {robot["name"] for robot in roster.robots()}
