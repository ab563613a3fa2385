"""The generated robot on two simulated computers (testsupport/hosts.py) whose network drops multicast, so only
the Discovery Server lets them meet: the leader arm on host "arm" drives the follower on host "bench", also
after the server crashed and was restarted by its supervisor (a follower started after that finds the
leader through the new server), and after bench's link was down for 5 s.

Each host's supervisor runs inside its host's namespaces (its own network and /dev/shm); the emulated
buses run in the test process, on ptys that both hosts see as files.
"""

import os
import re
import signal
import time
from pathlib import Path

import pytest

from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from testsupport import host_namespaces
from testsupport.host_supervisors import ready, start_supervisors, stop_supervisors, wait_for
from testsupport.hosts import virtual_hosts
from testsupport.joshuac_cli import joshuac

pytestmark = pytest.mark.process  # and ros, from ros_env

READY_TIMEOUT_S = 60.0  # both supervisors ready, nodes started cold on a busy 2-core machine
TRACKING_TIMEOUT_S = 20.0
RESTART_TIMEOUT_S = 20.0  # the crashed server started again and ready
LINK_DOWN_S = 5.0
TRACKING_TOLERANCE_TICKS = 3
SERVER_PORT = 11811  # inside host arm's own network namespace: nothing else can hold it
HOSTS = ("arm", "bench")
POSES = (
    {1: 1500, 2: 2500, 3: 1800, 4: 2300, 5: 1000, 6: 2600},  # before anything fails
    {1: 2600, 2: 1400, 3: 2200, 4: 1700, 5: 3000, 6: 1200},  # after the server's crash
    {1: 1900, 2: 2100, 3: 2900, 4: 1300, 5: 2000, 6: 2200},  # set while bench's link is down
)

DESCRIPTION = """
robot_config {{
  name: "two_computers"
  mode: MODE_TELEOPERATION
  host {{ name: "arm" address: "{arm}" }}
  host {{ name: "bench" address: "{bench}" }}
  discovery {{ server_host: "arm" port: {port} }}
  node {{
    name: "leader"
    type: ENCODER_PUBLISHER
    host: "arm"
    topic_name: "/leader/joint_states"
    serial_port: "{leader}"
  }}
  node {{
    name: "follower"
    type: ACTUATOR_SUBSCRIBER
    host: "bench"
    topic_name: "/leader/joint_states"
    serial_port: "{follower}"
    state_topic: "/follower/joint_states"
  }}
}}
"""


@pytest.fixture
def emulated_buses(tmp_path):
    leader = Sts3215Emulator(tmp_path / "ttyLEADER").start()
    follower = Sts3215Emulator(tmp_path / "ttyFOLLOWER").start()
    yield leader, follower
    leader.stop()
    follower.stop()


def started_pids(log: str, node: str) -> list[int]:
    """The pids the supervisor started `node` with, in order."""
    return [int(pid) for pid in re.findall(rf"^\[ *[\d.]+\] {node}: started pid (\d+)", log, re.M)]


def restarted(log: Path, node: str) -> bool:
    """`node` was started a second time and is ready again."""
    text = log.read_text()
    return len(started_pids(text, node)) == 2 and text.count(f"{node}: ready after") == 2


def test_the_leader_drives_the_follower_on_another_computer_through_a_server_crash_and_a_link_down(
    tmp_path, ros_env, emulated_buses
):
    leader_bus, follower_bus = emulated_buses

    def set_pose(pose: dict[int, int]) -> None:
        for servo_id, ticks in pose.items():
            leader_bus.move_by_hand(servo_id, ticks)

    def follower_at(pose: dict[int, int]) -> bool:
        return all(abs(follower_bus.position(i) - ticks) <= TRACKING_TOLERANCE_TICKS for i, ticks in pose.items())

    def positions() -> dict[int, int]:
        return {i: follower_bus.position(i) for i in POSES[0]}

    with virtual_hosts(*HOSTS) as network:
        network.block_multicast()
        source = tmp_path / "two_computers.pbtxt"
        source.write_text(
            DESCRIPTION.format(
                arm=network["arm"].address,
                bench=network["bench"].address,
                port=SERVER_PORT,
                leader=leader_bus.link,
                follower=follower_bus.link,
            )
        )
        out = tmp_path / "out"
        built = joshuac("build", source, "-o", out)
        assert built.returncode == 0, built.stderr
        supervisors, logs = start_supervisors(network, out, tmp_path, ros_env)
        try:
            wait_for(lambda: all(ready(path.read_text()) for path in logs.values()), READY_TIMEOUT_S, supervisors, logs)
            set_pose(POSES[0])
            assert follower_bus.wait_until(lambda: follower_at(POSES[0]), TRACKING_TIMEOUT_S), positions()

            [crashed] = started_pids(logs["arm"].read_text(), "discovery_server")
            os.kill(crashed, signal.SIGKILL)
            wait_for(lambda: restarted(logs["arm"], "discovery_server"), RESTART_TIMEOUT_S, supervisors, logs)
            # A follower started after the crash finds the leader through the restarted server only.
            [follower] = started_pids(logs["bench"].read_text(), "follower")
            os.kill(follower, signal.SIGKILL)
            wait_for(lambda: restarted(logs["bench"], "follower"), RESTART_TIMEOUT_S, supervisors, logs)
            set_pose(POSES[1])
            assert follower_bus.wait_until(lambda: follower_at(POSES[1]), TRACKING_TIMEOUT_S), positions()

            network["bench"].link_down()
            set_pose(POSES[2])
            time.sleep(LINK_DOWN_S)
            cut_off = follower_at(POSES[1])
            network["bench"].link_up()
            assert cut_off, positions()  # nothing reached bench while its link was down
            assert follower_bus.wait_until(lambda: follower_at(POSES[2]), TRACKING_TIMEOUT_S), positions()
        finally:
            codes = stop_supervisors(supervisors)
            outlived = {host.name: host_namespaces.network_namespace_pids(host.netns) for host in network}
        namespaces = [host.netns for host in network] + [network.switch]
    outputs = {name: path.read_text() for name, path in logs.items()}
    assert codes == dict.fromkeys(HOSTS, 0), outputs
    assert outlived == dict.fromkeys(HOSTS, []), outputs
    assert set(namespaces).isdisjoint(host_namespaces.network_namespaces())
    arm = outputs["arm"]
    assert f"discovery_server: started pid {crashed}" in arm
    assert "discovery_server: restarting in" in arm[arm.index(f"started pid {crashed}") :], arm
    assert "discovery_server" not in outputs["bench"], outputs["bench"]
