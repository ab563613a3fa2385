"""A Discovery Server killed without stopping starts again only once its clients have dropped it (restart_pause.py)."""

import os
import signal
import subprocess
import sys

import pytest

from joshua_runtime.discovery import restart_pause
from joshua_runtime.discovery.supervised import DEFAULT_PROFILE
from testsupport.dds_processes import ROOT, SERVER_READY_LINE, START_TIMEOUT_S, probe_server_from
from testsupport.dds_profiles import ServerTiming, server_profile
from testsupport.probe_output import ProbeOutput

PAUSE_LINE = "crashed less than 2 x its 5 s lease ago"
SLOW_LEASE = ServerTiming(lease_ms=5000)  # a pause (up to 11 s) long enough to probe within on a busy machine
NOTHING_LISTENS = "False nothing listens"


@pytest.mark.unit
def test_no_pause_without_a_heartbeat_and_twice_the_lease_after_the_last_beat(tmp_path):
    heartbeat = restart_pause.heartbeat_path("10.0.0.1", 11811, tmp_path)
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=1000.0) == 0.0
    restart_pause.beat(heartbeat)
    beaten = heartbeat.stat().st_mtime
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=beaten) == restart_pause.HEARTBEAT_S + 4.0
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=beaten + 3.0) == restart_pause.HEARTBEAT_S + 1.0
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=beaten + 10.0) == 0.0
    restart_pause.clear(heartbeat)
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=beaten) == 0.0


@pytest.mark.unit
def test_the_lease_comes_from_the_server_profile(tmp_path):
    assert restart_pause.lease_s(str(DEFAULT_PROFILE)) == 2.0
    assert restart_pause.lease_s("") == restart_pause.DEFAULT_LEASE_S
    silent = tmp_path / "no_lease.xml"
    silent.write_text('<dds xmlns="http://www.eprosima.com"><profiles/></dds>')
    assert restart_pause.lease_s(str(silent)) == restart_pause.DEFAULT_LEASE_S
    broken = tmp_path / "broken.xml"
    broken.write_text("<dds>")
    with pytest.raises(ValueError, match="is not XML"):
        restart_pause.lease_s(str(broken))


def test_a_profile_that_is_not_xml_gets_one_line_and_exit_code_2(tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text("<dds>")
    command = [sys.executable, "-m", "joshua_runtime.discovery.supervised", "--address", "10.0.0.1"]
    result = subprocess.run([*command, "--profile", str(broken)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and result.stderr.startswith(f"error: the server profile {broken} is not XML")
    assert len(result.stderr.splitlines()) == 1


def start_supervised(host, env, profile) -> ProbeOutput:
    command = [sys.executable, "-m", "joshua_runtime.discovery.supervised", "--address", host.address]
    command += ["--profile", str(profile)]
    process = host.popen(
        command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
    )
    return ProbeOutput(process)


def serving(server: ProbeOutput) -> bool:
    return server.wait_for(lambda output: any(SERVER_READY_LINE in line for line in output.lines()), START_TIMEOUT_S)


def test_a_killed_server_waits_out_twice_its_lease_and_a_stopped_one_starts_at_once(hosts, ros_env, tmp_path):
    profile = tmp_path / "server.xml"
    profile.write_text(server_profile(SLOW_LEASE))
    first = start_supervised(hosts["robot"], ros_env, profile)
    assert serving(first), first.tail()
    os.killpg(first.process.pid, signal.SIGKILL)  # the launcher and the server, as a crash of the node
    first.process.wait(START_TIMEOUT_S)

    second = start_supervised(hosts["robot"], ros_env, profile)
    assert second.wait_for(lambda output: any(PAUSE_LINE in line for line in output.lines()), START_TIMEOUT_S)
    assert probe_server_from(hosts["gpu"], hosts["robot"].address).startswith(NOTHING_LISTENS)
    assert serving(second), second.tail()
    assert probe_server_from(hosts["gpu"], hosts["robot"].address).startswith("True")
    second.process.send_signal(signal.SIGINT)
    assert second.process.wait(START_TIMEOUT_S) == 0

    third = start_supervised(hosts["robot"], ros_env, profile)
    assert serving(third), third.tail()
    assert not any(PAUSE_LINE in line for line in third.lines()), third.tail()
    third.process.send_signal(signal.SIGINT)
    assert third.process.wait(START_TIMEOUT_S) == 0


@pytest.mark.unit
def test_a_heartbeat_that_cannot_be_written_costs_only_the_pause(tmp_path):
    heartbeat = restart_pause.heartbeat_path("10.0.0.1", 11811, tmp_path / "missing")
    restart_pause.beat(heartbeat)
    restart_pause.clear(heartbeat)
    assert restart_pause.pause_needed_s(heartbeat, 2.0, now=0.0) == 0.0
