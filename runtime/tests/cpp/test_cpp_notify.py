"""sd_notify from the C++ binaries: READY=1 with what they serve (a lidar on its first scan), WATCHDOG=1, STOPPING=1."""

import os
import signal
import socket
import time

from cpp_support import NODE_START_TIMEOUT_S, CppNodeProcess, cpp_commands

WATCHDOG_USEC = 200_000
WATCHED_S = 1.0


def receive_until(listener: socket.socket, key: str, timeout_s: float = NODE_START_TIMEOUT_S) -> list[dict]:
    """Every notification up to and including the first holding `key`."""
    deadline = time.monotonic() + timeout_s
    received = []
    while time.monotonic() < deadline:
        listener.settimeout(max(0.01, deadline - time.monotonic()))
        try:
            data = listener.recv(4096)
        except TimeoutError:
            break
        fields = dict(line.split("=", 1) for line in data.decode().splitlines())
        received.append(fields)
        if key in fields:
            return received
    raise AssertionError(f"no {key} within {timeout_s} s; received {received}")


def cpp_argv(node_fields: str) -> list[str]:
    """The supervisor's command line of the only node, `cpp_node`, of a robot."""
    text = f'robot_config {{ name: "notify" mode: MODE_TELEOPERATION node {{ name: "cpp_node" {node_fields} }} }}'
    return cpp_commands(text)["cpp_node"]


def notified(ros_env, argv, name: str, **variables) -> tuple[socket.socket, CppNodeProcess]:
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    listener.bind("\0" + name)  # the abstract namespace, as supervisor.py uses it
    return listener, CppNodeProcess(argv, {**ros_env, "NOTIFY_SOCKET": f"@{name}", **variables})


def test_an_encoder_says_ready_with_what_it_serves_feeds_the_watchdog_and_says_stopping(ros_env, cpp_bin_dir, buses):
    bus = buses("ttyNOTIFY")
    argv = cpp_argv(
        f'type: ENCODER_PUBLISHER preferred_backend: CPP topic_name: "/cpp/joint_states" rate_hz: 40 '
        f'serial_port: "{bus.link}"'
    )
    listener, node = notified(ros_env, argv, f"joshua-test-cpp-notify-{os.getpid()}", WATCHDOG_USEC=str(WATCHDOG_USEC))
    try:
        ready = receive_until(listener, "READY")[-1]
        assert ready == {"READY": "1", "STATUS": f"publishing /cpp/joint_states, /diagnostics at 40 Hz on {bus.link}"}
        pings = []
        deadline = time.monotonic() + WATCHED_S
        while time.monotonic() < deadline:
            listener.settimeout(deadline - time.monotonic())
            try:
                if listener.recv(4096) == b"WATCHDOG=1":
                    pings.append(time.monotonic())
            except TimeoutError:
                break
        expected = WATCHED_S / (WATCHDOG_USEC / 1e6 / 2)  # one ping every half interval, give or take a poll
        assert expected - 3 <= len(pings) <= expected + 1
        code, _, stderr = node.stop(signal.SIGINT)
        assert code == 0, stderr
        assert f"ready: publishing /cpp/joint_states, /diagnostics at 40 Hz on {bus.link}" in stderr
        assert receive_until(listener, "STOPPING")[-1] == {"STOPPING": "1"}
    finally:
        node.kill()
        listener.close()


def test_a_lidar_is_ready_on_its_first_scan(ros_env, cpp_bin_dir, lidars):
    lidar = lidars("ttyNOTIFY")
    argv = cpp_argv(f'type: LIDAR_PUBLISHER preferred_backend: CPP topic_name: "/cpp/scan" serial_port: "{lidar.link}"')
    listener, node = notified(ros_env, argv, f"joshua-test-cpp-lidar-{os.getpid()}")
    try:
        ready = receive_until(listener, "READY")[-1]
        assert ready == {"READY": "1", "STATUS": f"first scan published; publishing /cpp/scan at 5 Hz on {lidar.link}"}
        assert node.stop(signal.SIGINT)[0] == 0
    finally:
        node.kill()
        listener.close()
