"""The fleet view's part of a rollout: each robot's release (build hash and time) and health from its status over
Zenoh, and the rollout's progress from `joshua-fleet deploy`'s state file, in `GET /api/robots`."""

import json

import pytest
from fleet_support import running_fleet, status, zenoh_peer

from joshua_runtime.dashboard.fleet_roster import Roster
from joshua_runtime.dashboard.fleet_status import StatusRejected, read_status
from joshua_runtime.rollout.inventory import Robot
from joshua_runtime.rollout.state import RolloutState

BUILD = "3a7d1c09b2e4" + "0" * 52
RUN = {
    "id": "5f0c9e21",
    "started": "2026-01-01T09:00:01.000+09:00",
    "build": BUILD,
    "built": "2026-01-01T08:59:00.250+09:00",
}


def test_a_status_with_its_run_gives_the_robots_release_and_health():
    roster = Roster()
    nodes = (("leader", "running"), ("follower", "running"))
    checked = read_status("arm_1", status("arm_1", nodes, run=RUN).encode())
    roster.update("arm_1", checked)
    [entry] = roster.robots()
    assert entry["release"] == {"build": "3a7d1c09b2e4", "built": "2026-01-01T08:59:00.250+09:00"}
    assert entry["health"] == {"ready": 2, "of": 2}
    roster.update("arm_2", read_status("arm_2", b'{"error": "supervisor unreachable"}'))
    assert roster.robots()[1]["release"] is None and roster.robots()[1]["health"] == {"ready": 0, "of": 0}


@pytest.mark.parametrize(
    ("run", "reason"),
    [
        ({"build": "not hex"}, "run.build: String should match pattern"),
        ({"build": BUILD, "built": "x" * 100}, "run.built: String should have at most"),
        ({"build": 7}, "run.build: Input should be a valid string"),
    ],
)
def test_a_run_outside_the_schema_is_rejected(run, reason):
    with pytest.raises(StatusRejected) as rejected:
        read_status("arm", json.dumps({"run": run}).encode())
    assert str(rejected.value).startswith(reason)


def test_api_robots_carries_each_robots_release_health_and_rollout(tmp_path):
    state_file = tmp_path / "rollout.json"
    robots = [Robot("arm_1", "arm_1", "10.0.0.11", "3a7d1c09b2e4"), Robot("arm_2", "arm_2", "10.0.0.12", "b" * 12)]
    state = RolloutState.begin(state_file, "lab", tmp_path, robots)
    state.update("arm_1", state="updated", message="ready: 2 of 2 nodes ready", seconds=12.5)
    state.update("arm_2", state="failed", step="gate", message="node crash failed", rolled_back_to="c" * 12)
    with running_fleet(tmp_path, "--rollout-state", str(state_file)) as fleet:
        with zenoh_peer(fleet.endpoint) as peer:
            peer.put("joshua/arm_1/status", status("arm_1", run=RUN))
            listed = fleet.wait_until(lambda robots: any(r["release"] for r in robots))
        by_name = {robot["name"]: robot for robot in listed}
        assert by_name["arm_1"]["release"]["build"] == "3a7d1c09b2e4"
        assert by_name["arm_1"]["health"] == {"ready": 1, "of": 1} and by_name["arm_1"]["online"] is True
        [rollout] = by_name["arm_1"]["rollout"]
        assert (rollout["state"], rollout["release"], rollout["seconds"]) == ("updated", "3a7d1c09b2e4", 12.5)
        # A robot of the rollout that publishes nothing (no dashboard) is listed with its rollout alone.
        arm_2 = by_name["arm_2"]
        assert (arm_2["online"], arm_2["last_seen_s"], arm_2["nodes"], arm_2["release"]) == (False, None, [], None)
        [rollout] = arm_2["rollout"]
        assert (rollout["state"], rollout["step"], rollout["rolled_back_to"]) == ("failed", "gate", "c" * 12)
        summary = fleet_rollout(fleet)
        assert (summary["fleet"], summary["state"]) == ("lab", "running")


def fleet_rollout(fleet) -> dict:
    from dashboard_support import get_json

    return get_json(f"{fleet.url}/api/rollout", fleet.token)


def test_the_fleet_page_shows_each_robots_release_health_and_rollout(tmp_path):
    from dashboard_support import browser, screenshot

    state_file = tmp_path / "rollout.json"
    robots = [Robot("arm_1", "arm_1", "10.0.0.11", "3a7d1c09b2e4"), Robot("arm_2", "arm_2", "10.0.0.12", "b" * 12)]
    state = RolloutState.begin(state_file, "lab", tmp_path, robots)
    state.update("arm_1", state="updated", message="ready: 2 of 2 nodes ready", seconds=12.5)
    state.update("arm_2", state="failed", step="gate", message="node crash failed", rolled_back_to="c" * 12)
    state.finish(succeeded=False)
    errors = []
    with running_fleet(tmp_path, "--rollout-state", str(state_file)) as fleet, zenoh_peer(fleet.endpoint) as peer:
        nodes = (("leader", "running"), ("follower", "running"))
        with browser() as chromium:
            page = chromium.new_page(viewport={"width": 1200, "height": 700})
            page.on("pageerror", lambda error: errors.append(str(error)))
            page.goto(fleet.url + "/")
            peer.put("joshua/arm_1/status", status("arm_1", nodes, run=RUN))
            page.get_by_test_id("release-arm_1").get_by_text(
                "release 3a7d1c09b2e4, built 2026-01-01 08:59:00"
            ).wait_for()
            assert page.get_by_test_id("health-arm_1").inner_text() == "ready: 2 of 2 nodes"
            assert page.get_by_test_id("rollout-arm_1").inner_text() == "release 3a7d1c09b2e4 rolled out in 12.5 s"
            failed = page.get_by_test_id("rollout-arm_2").inner_text()
            assert failed == f"failed at gate: node crash failed; back on {'c' * 12}"
            assert page.get_by_test_id("robot-arm_2").get_by_text("not heard from").is_visible()
            summary = page.get_by_test_id("rollout-summary").inner_text()
            assert summary.startswith("rollout of lab: failed, finished ") and summary.endswith(
                "1 of 2 on their new release"
            )
            screenshot(page, "fleet_rollout")
    assert errors == []
