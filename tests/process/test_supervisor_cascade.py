"""The generated supervisor's shutdown cascade: SIGINT, then SIGTERM, then SIGKILL, per process group."""

import signal

from supervisor_harness import Supervisor, alive, build, custom_node, events, log_times, robot, wait_until

GRACE_S = 0.3
SLACK_S = 2.0  # scheduling noise allowed on this shared machine when checking when a step happened


def started(log, count):
    return wait_until(lambda: len([e for e in events(log) if e[2] == "start"]) >= count, f"{count} starts")


def received(log, name):
    return [text for node, _, text in events(log) if node == name and text.startswith("got ")]


def stop_after_start(tmp_path, nodes, starts=None, signum=signal.SIGINT, **graces) -> tuple[int, str]:
    """Run a robot of `nodes` (logging to tmp_path/events.log) until `starts` processes started (one per
    node unless given), send `signum` to the supervisor; its exit code and log."""
    supervisor = Supervisor(build(tmp_path, robot(nodes, **graces)))
    try:
        started(tmp_path / "events.log", len(nodes) if starts is None else starts)
        supervisor.signal(signum)
        return supervisor.wait(), supervisor.log()
    finally:
        supervisor.close()


def test_cooperative_nodes_stop_on_sigint_and_the_supervisor_exits_0(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(tmp_path, [custom_node("a", log), custom_node("b", log)])
    assert code == 0
    assert received(log, "a") == ["got SIGINT exit"]
    assert received(log, "b") == ["got SIGINT exit"]
    assert "escalating" not in text


def test_sigterm_to_the_supervisor_also_starts_with_sigint_to_the_nodes(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(tmp_path, [custom_node("a", log)], signum=signal.SIGTERM)
    assert code == 0
    assert received(log, "a") == ["got SIGINT exit"]
    assert "received SIGTERM: stopping every node" in text


def test_node_ignoring_sigint_gets_sigterm_after_the_sigint_grace(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(
        tmp_path,
        [custom_node("stubborn", log, "SIGINT=ignore"), custom_node("a", log)],
        sigint=GRACE_S,
        sigterm=GRACE_S,
    )
    assert code == 1
    assert received(log, "stubborn") == ["got SIGINT ignore", "got SIGTERM exit"]
    assert received(log, "a") == ["got SIGINT exit"]
    [stop] = log_times(text, r"supervisor: received SIGINT")
    [term] = log_times(text, r"stubborn: still running: escalating to SIGTERM")
    assert GRACE_S <= term - stop < GRACE_S + SLACK_S
    assert "escalating to SIGKILL" not in text


def test_node_ignoring_sigint_and_sigterm_is_killed_after_both_graces(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(
        tmp_path, [custom_node("deaf", log, "SIGINT=ignore", "SIGTERM=ignore")], sigint=GRACE_S, sigterm=GRACE_S
    )
    assert code == 1
    assert received(log, "deaf") == ["got SIGINT ignore", "got SIGTERM ignore"]
    [stop] = log_times(text, r"supervisor: received SIGINT")
    [kill] = log_times(text, r"deaf: still running: escalating to SIGKILL")
    assert 2 * GRACE_S <= kill - stop < 2 * GRACE_S + SLACK_S
    assert "deaf: pid" in text and "killed by SIGKILL" in text


def test_a_second_stop_request_skips_to_the_next_step(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("stubborn", log, "SIGINT=ignore")], sigint=60, sigterm=60))
    supervisor = Supervisor(out)
    try:
        started(log, 1)
        supervisor.signal(signal.SIGINT)
        wait_until(lambda: received(log, "stubborn"), "the node to see SIGINT")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 1
    finally:
        supervisor.close()
    assert received(log, "stubborn") == ["got SIGINT ignore", "got SIGTERM exit"]
    assert "received SIGINT again: escalating now" in supervisor.log()


def test_grandchildren_in_the_node_group_get_the_cascade_too(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(tmp_path, [custom_node("parent", log, "grandchild=ignore")], starts=2)
    assert code == 1
    [grandchild] = [pid for name, pid, text in events(log) if name == "parent/grandchild"]
    assert not alive(grandchild)
    assert received(log, "parent") == ["got SIGINT exit"]
    assert "parent: still running: escalating to SIGKILL" in text


def test_a_grandchild_that_left_its_group_is_stopped_with_its_node(tmp_path):
    log = tmp_path / "events.log"
    code, text = stop_after_start(tmp_path, [custom_node("parent", log, "grandchild=escape")], starts=2)
    assert code == 1
    [grandchild] = [pid for name, pid, text in events(log) if name == "parent/grandchild"]
    assert not alive(grandchild)
    for stage in ("SIGINT", "SIGTERM", "SIGKILL"):
        assert f"parent: {stage} also to 1 process it started outside its group: {grandchild}" in text


def test_duration_runs_the_robot_then_stops_it_cleanly(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log)]))
    supervisor = Supervisor(out, "--duration", "0.5")
    try:
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
    assert [text for _, _, text in events(log)] == ["start", "got SIGINT exit"]
    assert "duration of 0.5 s elapsed: stopping every node" in supervisor.log()
