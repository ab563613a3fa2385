"""Restart policies, exponential backoff, max_restarts, critical nodes, and reaping (no zombies)."""

import re
import signal
import time

from supervisor_harness import Supervisor, build, custom_node, events, log_times, robot, wait_until, zombies_of

INITIAL_DELAY_S = 0.25  # process_launch.RESTART_DELAY_INITIAL_S, as the generated log reports it


def starts(log, name):
    return [pid for node, pid, text in events(log) if node == name and text == "start"]


def test_crashing_node_restarts_max_restarts_times_with_growing_delays_then_stops_the_robot(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot([custom_node("crash", log, "exit_after=0", "code=3", max_restarts="3"), custom_node("steady", log)]),
    )
    supervisor = Supervisor(out)
    try:
        assert supervisor.wait() == 4
    finally:
        supervisor.close()
    assert len(starts(log, "crash")) == 4
    text = supervisor.log()
    delays = [float(d) for d in re.findall(r"^\[[\s\d.]+\] crash: restarting in ([\d.]+) s", text, re.M)]
    assert delays == [INITIAL_DELAY_S, 2 * INITIAL_DELAY_S, 4 * INITIAL_DELAY_S]
    assert re.findall(r"crash: restarting in [\d.]+ s \((restart \d of \d)\)", text) == [
        "restart 1 of 3",
        "restart 2 of 3",
        "restart 3 of 3",
    ]
    exits = log_times(text, r"crash: pid \d+ exited with code 3")
    launches = log_times(text, r"crash: started pid")
    gaps = [start - exit for exit, start in zip(exits, launches[1:])]
    assert all(gap >= delay for gap, delay in zip(gaps, delays))
    assert gaps[0] < gaps[1] < gaps[2]
    assert "crash: failed for good after 3 restarts (max_restarts 3); critical node: stopping the robot" in text
    assert [text for node, _, text in events(log) if node == "steady"] == ["start", "got SIGINT exit"]


def test_a_non_critical_node_that_fails_for_good_leaves_the_robot_running(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [
                custom_node("flaky", log, "exit_after=0", "code=1", max_restarts="1", critical="false"),
                custom_node("steady", log),
            ]
        ),
    )
    supervisor = Supervisor(out)
    try:
        supervisor.wait_log(r"flaky: failed for good after 1 restarts .*not critical")
        assert supervisor.process.poll() is None
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 5
    finally:
        supervisor.close()
    assert len(starts(log, "flaky")) == 2
    assert [text for node, _, text in events(log) if node == "steady"] == ["start", "got SIGINT exit"]


def test_restart_policies_and_a_supervisor_that_ends_when_every_node_has_finished(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [
                custom_node("never", log, "exit_after=0", restart="RESTART_NEVER"),
                custom_node("on_failure", log, "exit_after=0", restart="RESTART_ON_FAILURE"),
                custom_node(
                    "always", log, "exit_after=0", restart="RESTART_ALWAYS", max_restarts="2", critical="false"
                ),
            ]
        ),
    )
    supervisor = Supervisor(out)
    try:
        assert supervisor.wait() == 5
    finally:
        supervisor.close()
    assert [len(starts(log, name)) for name in ("never", "on_failure", "always")] == [1, 1, 3]
    text = supervisor.log()
    assert "never: finished" in text and "on_failure: finished" in text
    assert "always: failed for good after 2 restarts" in text


def test_a_critical_restart_never_node_that_fails_stops_the_robot_at_once(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [custom_node("once", log, "exit_after=0", "code=2", restart="RESTART_NEVER"), custom_node("steady", log)]
        ),
    )
    supervisor = Supervisor(out)
    try:
        assert supervisor.wait() == 4
    finally:
        supervisor.close()
    assert len(starts(log, "once")) == 1
    assert "once: failed (RESTART_NEVER); critical node: stopping the robot" in supervisor.log()


def test_every_exited_process_is_reaped_at_once_no_zombie_is_left(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [
                custom_node(
                    "crash", log, "exit_after=0.05", "code=1", "grandchild=ignore", max_restarts="3", critical="false"
                ),
                custom_node("escaper", log, "exit_after=0.1", "grandchild=escape", restart="RESTART_NEVER"),
                custom_node("steady", log),
            ]
        ),
    )
    supervisor = Supervisor(out)
    seen: dict[int, float] = {}
    try:
        deadline = time.monotonic() + 2.5
        while time.monotonic() < deadline:
            now = time.monotonic()
            current = set(zombies_of(supervisor.pid))
            for pid in current:
                seen.setdefault(pid, now)
                assert now - seen[pid] < 0.5, f"process {pid} stayed a zombie of the supervisor"
            for pid in set(seen) - current:
                del seen[pid]
            time.sleep(0.01)
        wait_until(lambda: "crash: failed for good" in supervisor.log(), "the crash loop to end")
        supervisor.signal(signal.SIGINT)
        supervisor.wait()
    finally:
        supervisor.close()
    assert len(starts(log, "crash")) == 4
    assert "reaped leftover process" in supervisor.log()
