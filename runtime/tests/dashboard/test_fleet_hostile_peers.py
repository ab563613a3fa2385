"""Whatever a peer publishes, the fleet view keeps answering: statuses are checked against a schema before
they are kept, the table of robots is bounded, and robots not heard from go offline and then away.

A real `joshua-fleet` on loopback (where it admits peers without credentials) and a real Zenoh peer."""

import json

import pytest
from fleet_support import running_fleet, status, wait_linked, zenoh_peer

from joshua_runtime.dashboard.fleet_roster import MAX_ROBOTS
from joshua_runtime.dashboard.fleet_status import MAX_STATUS_BYTES

pytestmark = pytest.mark.process  # joshua-fleet

JUNK = {
    "a_list": "[1,2,3]",
    "a_string": '"abc"',
    "a_null": "null",
    "not_json": "{nodes:",
    "not_utf8": b"\xff\xfe{}",
    "nodes_string": '{"nodes": "abc"}',
    "nodes_numbers": '{"nodes": [1, 2]}',
    "node_name_number": '{"nodes": [{"name": 5, "state": "running"}]}',
    "node_state_markup": '{"nodes": [{"name": "n", "state": "<img src=x onerror=alert(1)>"}]}',
    "url_javascript": '{"nodes": [], "url": "javascript:alert(sessionStorage.getItem(\'joshua-dashboard-token\'))"}',
    "url_data": '{"nodes": [], "url": "data:text/html,<script>alert(1)</script>"}',
    "url_without_host": '{"nodes": [], "url": "http:///path"}',
    "url_spaces": '{"nodes": [], "url": "http://a b/"}',
    "nodes_twice": '{"nodes": [{"name": "n", "state": "running"}, {"name": "n", "state": "stopped"}]}',
    "error_object": '{"error": {"a": 1}}',
    "pid_huge": '{"nodes": [{"name": "n", "state": "running", "pid": 1e400}]}',
    "robot_other": json.dumps({"robot": "someone_else", "nodes": []}),
    "deep": "[" * 100_000,
    "too_many_nodes": json.dumps({"nodes": [{"name": f"n{i}", "state": "running"} for i in range(5000)]}),
    "oversized": json.dumps({"nodes": [], "error": "x" * (MAX_STATUS_BYTES + 1)}),
    "over_zenohs_limit": json.dumps({"nodes": [], "error": "x" * (4 * MAX_STATUS_BYTES)}),
}
BAD_NAMES = ("Upper", "9starts_with_digit", "with-dash", "x" * 65)


def test_junk_statuses_are_dropped_and_the_list_keeps_answering(tmp_path):
    with running_fleet(tmp_path) as fleet:
        with zenoh_peer(fleet.endpoint) as peer:
            wait_linked(peer)
            for name, payload in JUNK.items():
                peer.put(f"joshua/{name}/status", payload)
            for name in BAD_NAMES:
                peer.put(f"joshua/{name}/status", status(name))
            peer.put("joshua/good/status", status("good"))
            entry = fleet.wait_for("good")  # the peer's puts arrive in order: all the junk was handled
        assert fleet.names() == {"good"}
        assert entry["url"] == "http://good.example:8640/"
        assert entry["online"] is True
        assert fleet.process.poll() is None


def test_a_valid_status_replaces_only_its_own_robots_entry(tmp_path):
    with running_fleet(tmp_path) as fleet:
        with zenoh_peer(fleet.endpoint) as peer:
            wait_linked(peer)
            peer.put("joshua/arm/status", status("arm", nodes=[("leader", "running")]))
            peer.put("joshua/arm/status", '{"nodes": "abc"}')  # junk keeps the last good status
            peer.put("joshua/base/status", status("base"))
            fleet.wait_for("base")
            arm = fleet.wait_for("arm")
        assert [node["name"] for node in arm["nodes"]] == ["leader"]


def test_the_table_of_robots_is_bounded(tmp_path):
    with running_fleet(tmp_path) as fleet:
        with zenoh_peer(fleet.endpoint) as peer:
            wait_linked(peer)
            for index in range(MAX_ROBOTS + 100):
                peer.put(f"joshua/junk_{index}/status", status(f"junk_{index}"))
            peer.put("joshua/junk_0/status", status("junk_0", error="last"))  # a known robot is still updated
            fleet.wait_until(lambda robots: any(r["name"] == "junk_0" and r["error"] == "last" for r in robots))
        robots = fleet.robots()
        assert len(robots) == MAX_ROBOTS
        assert f"junk_{MAX_ROBOTS}" not in {robot["name"] for robot in robots}


def test_a_silent_robot_is_shown_offline_then_forgotten(tmp_path):
    with running_fleet(tmp_path, "--offline-after", "1", "--forget-after", "3") as fleet:
        with zenoh_peer(fleet.endpoint) as peer:
            wait_linked(peer)
            peer.put("joshua/quiet/status", status("quiet"))
            assert fleet.wait_for("quiet")["online"] is True
            fleet.wait_until(lambda robots: [r["online"] for r in robots if r["name"] == "quiet"] == [False])
            fleet.wait_until_gone("quiet")
            peer.put("joshua/quiet/status", status("quiet"))  # heard from again: back in the list
            assert fleet.wait_for("quiet")["online"] is True
