"""sd_notify from a real node process: READY=1 with what it serves, WATCHDOG=1 from its loop, STOPPING=1;
EXTEND_TIMEOUT_USEC while a stop takes longer."""

import os
import signal
import socket
import time

from joshua_runtime.notify import STOP_EXTENSION_ASK_S, STOP_EXTENSION_S, Notifier
from testsupport.compiled_settings import compiled_node

RECEIVE_TIMEOUT_S = 30.0
WATCHDOG_USEC = 200_000
WATCHED_S = 1.0


def receive_until(listener: socket.socket, key: str, timeout_s: float = RECEIVE_TIMEOUT_S) -> list[dict]:
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


def test_a_node_says_ready_with_what_it_serves_feeds_the_watchdog_and_says_stopping(start_node):
    name = f"joshua-test-notify-{os.getpid()}"
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as listener:
        listener.bind("\0" + name)  # the abstract namespace, as supervisor.py uses it
        settings = compiled_node(
            'name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 40'
        )
        node = start_node(settings, NOTIFY_SOCKET=f"@{name}", WATCHDOG_USEC=str(WATCHDOG_USEC))
        ready = receive_until(listener, "READY")[-1]
        assert ready == {"READY": "1", "STATUS": "publishing /leader/joint_states at 40 Hz"}
        pings = []
        deadline = time.monotonic() + WATCHED_S
        while time.monotonic() < deadline:
            listener.settimeout(deadline - time.monotonic())
            try:
                if listener.recv(4096) == b"WATCHDOG=1":
                    pings.append(time.monotonic())
            except TimeoutError:
                break
        expected = WATCHED_S / (WATCHDOG_USEC / 1e6 / 2)  # one ping every half interval, give or take a spin slice
        assert expected - 3 <= len(pings) <= expected + 1
        code, _, _ = node.stop(signal.SIGINT)
        assert code == 0
        assert receive_until(listener, "STOPPING")[-1] == {"STOPPING": "1"}


def test_a_path_socket_works_and_no_socket_means_silence(tmp_path):
    path = tmp_path / "notify"
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as listener:
        listener.bind(str(path))
        environ = {"NOTIFY_SOCKET": str(path), "WATCHDOG_USEC": "1000000", "WATCHDOG_PID": "1"}
        notifier = Notifier.from_environment(environ)
        assert environ == {}  # taken out: a child process of the node does not speak for it
        assert notifier.watchdog_interval_s is None  # the watchdog was meant for process 1, not us
        assert notifier.ready("serving\nthings")
        assert listener.recv(4096) == b"READY=1\nSTATUS=serving things"
    assert not Notifier.from_environment({}).ready("nobody listens")


def test_more_time_to_stop_is_asked_for_again_and_again_while_it_lasts_and_never_after(tmp_path):
    path = tmp_path / "notify"
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as listener:
        listener.bind(str(path))
        notifier = Notifier(str(path))
        with notifier.more_time_to_stop("saving 3 frames"):
            asks = [receive_until(listener, "EXTEND_TIMEOUT_USEC")[-1] for _ in range(2)]
        listener.settimeout(STOP_EXTENSION_ASK_S * 2)
        try:
            after = listener.recv(4096)
        except TimeoutError:
            after = None
        notifier.close()
    ask = {"EXTEND_TIMEOUT_USEC": str(int(STOP_EXTENSION_S * 1e6)), "STATUS": "saving 3 frames"}
    assert asks == [ask, ask]
    assert after is None
    with Notifier(None).more_time_to_stop("nobody to ask"):
        pass  # without a manager, nothing is sent and nothing fails
