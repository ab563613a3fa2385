"""A C++ node's wait loop sleeps while it has nothing to do and SIGINT wakes it at once.

The loop waits on its subscriptions and a guard condition that a stop signal triggers, with no
timeout but the next timer or watchdog ping. So a node with nothing due sleeps: its main thread is
not woken at all between two samples of its context switches (a loop that polled for the signal
every 50 ms would wake 20 times a second), and SIGINT still ends it with exit code 0, which only the
signal can have woken. Repeated, with the signal sent at a random moment each time. The delay from
signal to exit as a distribution is measured by bench/cpp_nodes.py.
"""

import os
import random
import signal
import socket
import time
from pathlib import Path

import pytest
from cpp_support import STOP_BOUND_S, CppNodeProcess, cpp_commands
from test_cpp_notify import receive_until

TRIALS = 4
SETTLE_S = 0.3  # after READY, for the first pass of the loop to end
IDLE_WINDOW_S = 1.0
# Wake-ups of the main thread allowed in the window; polling every 50 ms gives about 20.
MAX_IDLE_WAKEUPS = 2
SLOW = "diagnostics_rate_hz: 0.001"  # servo health every 1000 s: never during a trial
NODES = {
    "actuator (subscriptions)": 'type: ACTUATOR_SUBSCRIBER topic_name: "/cpp/command" command_timeout_s: 0',
    "encoder (timers only)": 'type: ENCODER_PUBLISHER topic_name: "/cpp/joint_states" rate_hz: 0.01',
}


def main_thread_switches(pid: int) -> int:
    """Times the main thread gave up the CPU to wait (its voluntary context switches)."""
    for line in Path(f"/proc/{pid}/task/{pid}/status").read_text().splitlines():
        if line.startswith("voluntary_ctxt_switches:"):
            return int(line.split()[1])
    raise AssertionError(f"no voluntary_ctxt_switches in /proc/{pid}/task/{pid}/status")


@pytest.mark.parametrize("fields", NODES.values(), ids=NODES.keys())
def test_an_idle_node_sleeps_until_sigint_wakes_it(ros_env, cpp_bin_dir, buses, fields):
    bus = buses("ttyWAKE")
    text = (
        f'robot_config {{ name: "wake" mode: MODE_TELEOPERATION node {{ name: "cpp_node" preferred_backend: CPP '
        f'{fields} {SLOW} serial_port: "{bus.link}" }} }}'
    )
    argv = cpp_commands(text)["cpp_node"]
    jitter = random.Random(0)
    trials = []
    for trial in range(TRIALS):
        name = f"joshua-test-cpp-wake-{os.getpid()}-{trial}"
        listener = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        listener.bind("\0" + name)
        node = CppNodeProcess(argv, {**ros_env, "NOTIFY_SOCKET": f"@{name}"})
        try:
            try:
                receive_until(listener, "READY")
            except AssertionError as exc:
                raise AssertionError(f"{exc}; the node: {node.failure()}") from None
            time.sleep(SETTLE_S)
            before = main_thread_switches(node.process.pid)
            time.sleep(IDLE_WINDOW_S)
            wakeups = main_thread_switches(node.process.pid) - before
            time.sleep(jitter.random() * 0.05)
            code, seconds, stderr = node.stop(signal.SIGINT)
            trials.append((wakeups, code, round(1000 * seconds, 1)))
            assert code == 0, stderr
        finally:
            node.kill()
            listener.close()
    summary = f"(wake-ups in {IDLE_WINDOW_S} s idle, exit code, ms from SIGINT to exit) per trial: {trials}"
    assert all(wakeups <= MAX_IDLE_WAKEUPS for wakeups, _, _ in trials), summary
    print(summary)
    assert all(ms < 1000 * STOP_BOUND_S for _, _, ms in trials), summary
