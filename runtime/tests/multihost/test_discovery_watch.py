"""Telling whether a host's Discovery Server answers: the RTPS probe against the real server, and the watch's rule.

The probe runs inside the simulated hosts against `fast-discovery-server` itself; the watch's timing rule
is checked on a simulated clock, and its command in a host whose link goes down and comes back.
"""

import signal
import socket
import subprocess
import sys

import pytest

from joshua_runtime.discovery import watch
from joshua_runtime.discovery.probe import ProbeResult
from testsupport.dds_processes import ROOT, SERVER_PORT, probe_server_from, start_server
from testsupport.probe_output import ProbeOutput

CHANGE_TIMEOUT_S = 30.0
ANSWER = ProbeResult(True, "answered in 0.4 ms", 0.0004, 0)
SILENCE = ProbeResult(False, "no answer within 1 s")


def test_the_probe_is_answered_by_a_running_server_and_names_it(hosts, ros_env):
    start_server(hosts["robot"], ros_env)
    assert probe_server_from(hosts["gpu"], hosts["robot"].address).startswith(
        "True discovery server 0 on 10.201.0.1:11811"
    )
    assert probe_server_from(hosts["gpu"], hosts["robot"].address, 0).startswith("True")
    assert (
        probe_server_from(hosts["gpu"], hosts["robot"].address, 1)
        == "False the server on 10.201.0.1:11811 has id 0, not 1"
    )


def test_the_probe_tells_a_host_without_server_from_a_host_out_of_reach(hosts):
    assert probe_server_from(hosts["gpu"], hosts["robot"].address) == (
        "False nothing listens on 10.201.0.1:11811 (its host answered: port unreachable)"
    )
    hosts["robot"].link_down()
    assert probe_server_from(hosts["gpu"], hosts["robot"].address) == "False no answer from 10.201.0.1:11811 within 1 s"


def feed(server_watch, results, start_s=0.0):
    """Record each result at the time the watch asked for it; the changes with their times."""
    changes, now = [], start_s
    for result in results:
        now = max(now, server_watch.next_probe_s)
        change = server_watch.record(result, now)
        if change is not None:
            changes.append((now, change.state))
    return changes, now


@pytest.mark.unit
def test_a_server_that_never_answers_is_declared_unreachable_within_5_s():
    server_watch = watch.ServerWatch("10.0.0.1:11811", 0.0)
    changes, _ = feed(server_watch, [SILENCE] * 20)
    assert changes[0][1] == watch.UNREACHABLE and changes[0][0] <= 5.0
    assert len(changes) == 1


@pytest.mark.unit
def test_a_server_that_stops_answering_is_declared_unreachable_within_5_s_of_its_last_answer():
    server_watch = watch.ServerWatch("10.0.0.1:11811", 0.0)
    changes, _ = feed(server_watch, [ANSWER] * 3)
    last_answer = server_watch.last_answer_s
    changes, _ = feed(server_watch, [SILENCE] * 20, last_answer)
    assert changes[0][1] == watch.UNREACHABLE
    assert changes[0][0] - last_answer <= 5.0


@pytest.mark.unit
def test_an_unreachable_server_is_retried_with_doubling_back_off_and_found_again():
    server_watch = watch.ServerWatch("10.0.0.1:11811", 0.0)
    while server_watch.state != watch.UNREACHABLE:
        server_watch.record(SILENCE, server_watch.next_probe_s)
    delays = [server_watch.next_probe_s - server_watch.since_s]
    for _ in range(7):
        before = server_watch.next_probe_s
        server_watch.record(SILENCE, before)
        delays.append(server_watch.next_probe_s - before)
    assert delays == [1.0, 2.0, 4.0, 8.0, 16.0, watch.BACKOFF_MAX_S, watch.BACKOFF_MAX_S, watch.BACKOFF_MAX_S]
    change = server_watch.record(ANSWER, server_watch.next_probe_s)
    assert change.state == watch.REACHABLE and "answers again after" in change.line
    assert server_watch.next_probe_s - server_watch.last_answer_s == watch.HEALTHY_PERIOD_S
    assert server_watch.backoff_s == watch.BACKOFF_S


@pytest.fixture
def notify_socket(tmp_path):
    """A Unix datagram socket standing for the process manager; its path is the NOTIFY_SOCKET value."""
    path = tmp_path / "notify"
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as manager:
        manager.bind(str(path))
        manager.settimeout(CHANGE_TIMEOUT_S)
        yield path, manager


def notification(manager) -> dict[str, str]:
    return dict(line.split("=", 1) for line in manager.recv(4096).decode().splitlines())


def test_the_watch_reports_each_change_to_its_output_and_its_process_manager(hosts, ros_env, notify_socket):
    path, manager = notify_socket
    start_server(hosts["robot"], ros_env)
    command = [
        sys.executable,
        "-m",
        "joshua_runtime.discovery.watch",
        "--server",
        f"{hosts['robot'].address}:{SERVER_PORT}",
    ]
    env = dict(ros_env, NOTIFY_SOCKET=str(path))
    process = hosts["gpu"].popen(
        command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    output = ProbeOutput(process)
    first = notification(manager)
    assert first["READY"] == "1" and first[watch.STATE_FIELD] == watch.REACHABLE
    hosts["gpu"].link_down()
    lost = notification(manager)
    assert lost[watch.STATE_FIELD] == watch.UNREACHABLE and "unreachable: no answer" in lost["STATUS"]
    hosts["gpu"].link_up()
    back = notification(manager)
    assert back[watch.STATE_FIELD] == watch.REACHABLE and "READY" not in back
    assert "answers again after" in back["STATUS"]
    process.send_signal(signal.SIGINT)
    assert process.wait(CHANGE_TIMEOUT_S) == 0
    assert notification(manager) == {"STOPPING": "1"}
    lines = output.lines()
    assert [line.split()[3] for line in lines] == ["reachable:", "unreachable:", "answers"], lines
