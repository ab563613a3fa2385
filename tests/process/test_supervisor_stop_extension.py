"""A node that needs longer than the SIGINT grace to stop cleanly asks for more time, as systemd allows:
EXTEND_TIMEOUT_USEC=N on NOTIFY_SOCKET while it stops holds its SIGTERM until N µs after the last ask.

The recorder does that while it saves frames recorded before its dataset writer had loaded LeRobot."""

import runpy
import signal

from supervisor_harness import (
    Supervisor,
    build,
    ctl,
    events,
    log_times,
    robot,
    wait_started,
)

from joshua_codegen.supervisor.ctl import CTL_TIMEOUT_S
from testsupport.slow_stopper import slow_stopper_node

GRACE_S = 0.3
EXTENSION_S = 1.0  # what the node asks for at each ask, more than three graces
ASKING_S = 2.0  # how long a node that stops slowly keeps asking before it exits


def slow_stopper(directory, name: str, every_s: float, asking_s: float, then: str) -> str:
    return slow_stopper_node(directory, name, EXTENSION_S, every_s, asking_s, then)


def test_a_node_asking_for_more_time_while_it_saves_is_not_escalated_and_the_run_ends_0(tmp_path):
    out = build(tmp_path, robot([slow_stopper(tmp_path, "recorder", GRACE_S, ASKING_S, "exit")], GRACE_S, GRACE_S))
    supervisor = Supervisor(out)
    try:
        wait_started(tmp_path / "events.log", "recorder")
        supervisor.signal()
        code = supervisor.wait(ASKING_S + EXTENSION_S + 10.0)
    finally:
        supervisor.close()
    text = supervisor.log()
    assert [e[2] for e in events(tmp_path / "events.log")] == ["start", "got SIGINT saving", "saved"], text
    assert code == 0, text
    assert "escalating" not in text
    assert f"recorder: stopping takes longer: it asks for {EXTENSION_S:g} s more (saving)" in text


def test_a_node_that_stops_asking_gets_sigterm_once_its_last_extension_ran_out(tmp_path):
    out = build(tmp_path, robot([slow_stopper(tmp_path, "recorder", 10.0, 0.1, "stay")], GRACE_S, GRACE_S))
    supervisor = Supervisor(out)
    try:
        wait_started(tmp_path / "events.log", "recorder")
        supervisor.signal()
        code = supervisor.wait(EXTENSION_S + 10.0)
    finally:
        supervisor.close()
    text = supervisor.log()
    assert [e[2] for e in events(tmp_path / "events.log")] == ["start", "got SIGINT saving", "got SIGTERM exit"], text
    assert code == 1, text
    (asked,) = log_times(text, r"recorder: stopping takes longer")
    (escalated,) = log_times(text, r"recorder: still running: escalating to SIGTERM")
    assert escalated - asked >= EXTENSION_S - 0.05, text  # held for the extension asked (log stamps round to 1 ms)


def test_a_node_stopped_over_the_control_socket_may_ask_for_more_time_too(tmp_path):
    out = build(tmp_path, robot([slow_stopper(tmp_path, "recorder", GRACE_S, ASKING_S, "exit")], GRACE_S, GRACE_S))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock))
    try:
        wait_started(tmp_path / "events.log", "recorder")
        stopped = ctl(out, sock, "stop", "recorder")
        assert stopped.returncode == 0, stopped.stderr
        assert "escalating" not in supervisor.log()
        assert [e[2] for e in events(tmp_path / "events.log")] == ["start", "got SIGINT saving", "saved"]
    finally:
        supervisor.signal(signal.SIGINT)
        code = supervisor.wait()
    assert code == 0, supervisor.log()


def test_ctl_stop_waits_for_a_node_that_asks_for_more_time_than_ctl_waits_by_default(tmp_path):
    # ctl waits CTL_TIMEOUT_S for an answer; a node may hold its stop up to STOP_EXTENSION_MAX_S after its
    # SIGINT, and the supervisor answers the stop once the node has stopped: ctl waits that long too.
    asking_s = CTL_TIMEOUT_S + 2.0
    out = build(tmp_path, robot([slow_stopper(tmp_path, "recorder", GRACE_S, asking_s, "exit")], GRACE_S, GRACE_S))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock))
    try:
        wait_started(tmp_path / "events.log", "recorder")
        stopped = ctl(out, sock, "stop", "recorder", timeout=asking_s + 30.0)
        assert stopped.returncode == 0, stopped.stderr
        assert [e[2] for e in events(tmp_path / "events.log")] == ["start", "got SIGINT saving", "saved"]
    finally:
        supervisor.signal(signal.SIGINT)
        code = supervisor.wait()
    assert code == 0, supervisor.log()


def test_ctl_waits_for_a_stop_as_long_as_the_robots_own_graces_may_take(tmp_path):
    # An arm that parks before it powers down may be given minutes to stop: ctl's wait for a stop, a restart or
    # a reload covers the cascade of the robot it was built for, not only the default graces.
    sigint_grace_s, sigterm_grace_s = 200.0, 60.0
    node = slow_stopper(tmp_path, "arm", GRACE_S, ASKING_S, "exit")
    out = build(tmp_path, robot([node], sigint_grace_s, sigterm_grace_s))
    built = runpy.run_path(str(out / "supervisor.py"), run_name="built")  # the build's data and code, not run
    assert (built["SIGINT_GRACE_S"], built["SIGTERM_GRACE_S"]) == (sigint_grace_s, sigterm_grace_s)
    assert built["CTL_STOPPING_TIMEOUT_S"] > sigint_grace_s + sigterm_grace_s
