"""Readiness through supervisor.py: a runtime node counts as ready when it sends READY=1, not when it starts."""

import os
import re
import signal
import socket

from supervisor_harness import PYTHON, Supervisor, build, custom_node, quoted, robot, wait_started


def test_the_robot_is_ready_when_every_node_said_so(tmp_path, ros_env):
    leader = 'node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 40 }'
    out = build(tmp_path, robot([leader, custom_node("tool", tmp_path / "events.log")]))
    upstream = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)  # as systemd would give a Type=notify service
    upstream.bind(f"\0joshua-test-upstream-{os.getpid()}")
    env = dict(ros_env, NOTIFY_SOCKET=f"@joshua-test-upstream-{os.getpid()}")
    supervisor = Supervisor(out, "--status-interval", "0.2", env=env)
    try:
        supervisor.wait_log(r"started: 2 of 2 nodes running \([\d.]+ ms after start\); waiting for them to be ready")
        supervisor.wait_log(r"tool: ready after [\d.]+ s: a CUSTOM program: ready when started")
        supervisor.wait_log(r"leader: running pid \d+ for [\d.]+ s, Python, not ready yet, 0 restarts")
        ready = supervisor.wait_log(r"leader: ready after ([\d.]+) s: publishing /leader/joint_states at 40 Hz")
        summary = supervisor.wait_log(r"supervisor: ready: 2 of 2 nodes ready \(([\d.]+) s after start\)")
        assert float(summary.group(1)) >= float(ready.group(1))
        supervisor.wait_log(r"leader: running pid \d+ for [\d.]+ s, Python, ready, 0 restarts")
        upstream.settimeout(5)
        assert upstream.recv(4096) == b"READY=1\nSTATUS=2 of 2 nodes ready"  # passed on once, by the supervisor
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
        upstream.close()
    log = supervisor.log()
    assert log.index("leader: ready after") < log.index("supervisor: ready: 2 of 2")
    assert len(re.findall(r"supervisor: ready: ", log)) == 1


def test_a_robot_of_custom_nodes_only_is_ready_without_status_lines(tmp_path):
    """CUSTOM programs are ready when started: nothing else wakes the loop, yet the ready line and READY=1 come."""
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log), custom_node("b", log)]))
    upstream = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    upstream.bind(f"\0joshua-test-custom-upstream-{os.getpid()}")
    env = dict(os.environ, NOTIFY_SOCKET=f"@joshua-test-custom-upstream-{os.getpid()}")
    supervisor = Supervisor(out, "--no-control", "--log-dir", "", env=env)
    try:
        supervisor.wait_log(r"supervisor: ready: 2 of 2 nodes ready \([\d.]+ s after start\)")
        upstream.settimeout(5)
        assert upstream.recv(4096) == b"READY=1\nSTATUS=2 of 2 nodes ready"
        for name in ("a", "b"):  # ready when started is the supervisor's view; they stop cleanly from then on
            wait_started(log, name)
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
        upstream.close()
    assert "status:" not in supervisor.log()


# Fails at its first start (creating the file named by its argument), runs from its second on.
FAILS_ONCE = "import os, sys, time\nif not os.path.exists(sys.argv[1]):\n    open(sys.argv[1], 'w').close()\n    sys.exit(1)\ntime.sleep(3600)\n"


def test_a_custom_node_restarted_by_its_policy_makes_the_robot_ready_again(tmp_path):
    args = ", ".join(quoted(arg) for arg in ["-c", FAILS_ONCE, str(tmp_path / "failed-once")])
    once = f'node {{ name: "once" type: CUSTOM executable: "{PYTHON}" args: [{args}] restart: RESTART_ON_FAILURE }}'
    out = build(tmp_path, robot([custom_node("a", tmp_path / "events.log"), once]))
    supervisor = Supervisor(out, "--no-control", "--log-dir", "")
    try:
        supervisor.wait_log(r"once: restarting in [\d.]+ s \(restart 1 of")
        supervisor.wait_log(r"(?s)once: started pid .*once: started pid .*supervisor: ready: 2 of 2 nodes ready")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
