"""A robot on three hosts, each host's supervisor a plain process on this machine: the leader arm on one host
drives the follower on another through the Discovery Server that a third part of the build names.

Every host here is 127.0.0.x, the test's own ROS domain, and ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST: the
generated profiles make every process a client of the server, so no multicast discovery is involved.
"""

import re
import signal
import socket
import subprocess
import sys
import time

import pytest

from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from testsupport.joshuac_cli import joshuac

READY_TIMEOUT_S = 60.0
TRACKING_TIMEOUT_S = 20.0
STOP_TIMEOUT_S = 15.0
POLL_S = 0.1
TRACKING_TOLERANCE_TICKS = 3
HOSTS = ("arm", "bench", "station")

DESCRIPTION = """
robot_config {{
  name: "split_arm"
  mode: MODE_TELEOPERATION
  host {{ name: "arm" address: "127.0.0.1" }}
  host {{ name: "bench" address: "127.0.0.2" }}
  host {{ name: "station" address: "127.0.0.3" }}
  discovery {{ server_host: "arm" port: {port} }}
  node {{
    name: "leader"
    type: ENCODER_PUBLISHER
    host: "bench"
    topic_name: "/leader/joint_states"
    serial_port: "{leader}"
  }}
  node {{
    name: "follower"
    type: ACTUATOR_SUBSCRIBER
    topic_name: "/leader/joint_states"
    serial_port: "{follower}"
    state_topic: "/follower/joint_states"
  }}
  node {{
    name: "state_publisher"
    type: ROBOT_STATE_PUBLISHER
    host: "station"
    topic_name: "/follower/joint_states"
  }}
}}
"""


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def ready_line(log: str) -> bool:
    return re.search(r"^\[ *[\d.]+\] supervisor: ready: (\d+) of \1 nodes ready", log, re.M) is not None


@pytest.fixture
def emulated_buses(tmp_path):
    leader = Sts3215Emulator(tmp_path / "ttyLEADER").start()
    follower = Sts3215Emulator(tmp_path / "ttyFOLLOWER").start()
    yield leader, follower
    leader.stop()
    follower.stop()


def start_hosts(out, tmp_path, env) -> dict[str, subprocess.Popen]:
    supervisors = {}
    for host in HOSTS:
        with open(tmp_path / f"{host}.log", "w") as log:
            supervisors[host] = subprocess.Popen(
                [
                    sys.executable,
                    str(out / "hosts" / host / "supervisor.py"),
                    "--control-socket",
                    str(tmp_path / "control" / f"{host}.sock"),
                ],
                stdout=log,
                stderr=subprocess.STDOUT,
                env=env,
            )
    return supervisors


def stop_hosts(supervisors: dict[str, subprocess.Popen]) -> dict[str, int | None]:
    for supervisor in supervisors.values():
        supervisor.send_signal(signal.SIGINT)
    codes = {}
    for host, supervisor in supervisors.items():
        try:
            codes[host] = supervisor.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            supervisor.wait()
            codes[host] = None
    return codes


def test_the_leader_on_one_host_drives_the_follower_on_another_through_the_discovery_server(
    tmp_path, ros_env, emulated_buses
):
    leader_bus, follower_bus = emulated_buses
    source = tmp_path / "split_arm.pbtxt"
    source.write_text(DESCRIPTION.format(port=free_udp_port(), leader=leader_bus.link, follower=follower_bus.link))
    out = tmp_path / "out"
    built = joshuac("build", source, "-o", out)
    assert built.returncode == 0, built.stderr
    supervisors = start_hosts(out, tmp_path, ros_env)
    logs = {host: tmp_path / f"{host}.log" for host in HOSTS}
    try:
        deadline = time.monotonic() + READY_TIMEOUT_S
        while not all(ready_line(path.read_text()) for path in logs.values()):
            ended = [host for host, supervisor in supervisors.items() if supervisor.poll() is not None]
            assert not ended and time.monotonic() < deadline, {h: p.read_text() for h, p in logs.items()}
            time.sleep(POLL_S)
        pose = {1: 1500, 2: 2500, 3: 1800, 4: 2300, 5: 1000, 6: 2600}
        for servo_id, ticks in pose.items():
            leader_bus.move_by_hand(servo_id, ticks)

        def follower_tracks() -> bool:
            return all(abs(follower_bus.position(i) - ticks) <= TRACKING_TOLERANCE_TICKS for i, ticks in pose.items())

        assert follower_bus.wait_until(follower_tracks, TRACKING_TIMEOUT_S), {i: follower_bus.position(i) for i in pose}
    finally:
        codes = stop_hosts(supervisors)
    outputs = {host: path.read_text() for host, path in logs.items()}
    assert codes == dict.fromkeys(HOSTS, 0), outputs
    arm = outputs["arm"]
    # The server starts first, and the follower only once the server is ready.
    assert arm.index("discovery_server: ready after") < arm.index("follower: started pid"), arm
    assert "leader: started pid" in outputs["bench"] and "discovery_server" not in outputs["bench"]
    assert "state_publisher: ready after" in outputs["station"], outputs["station"]


def test_a_discovery_server_that_cannot_listen_holds_the_other_nodes_then_stops_its_host(tmp_path, ros_env):
    taken = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    taken.bind(("127.0.0.1", 0))
    source = tmp_path / "split_arm.pbtxt"
    source.write_text(
        DESCRIPTION.format(port=taken.getsockname()[1], leader=tmp_path / "ttyNONE", follower=tmp_path / "ttyNONE2")
    )
    out = tmp_path / "out"
    assert joshuac("build", source, "-o", out).returncode == 0
    try:
        done = subprocess.run(
            [sys.executable, str(out / "hosts" / "arm" / "supervisor.py"), "--skip-preflight", "--no-control"],
            capture_output=True,
            text=True,
            env=ros_env,
            timeout=READY_TIMEOUT_S,
        )
    finally:
        taken.close()
    assert done.returncode == 4, done.stderr  # a critical node failed for good
    assert "Discovery Server wasn't able to allocate the specified listening port" in done.stdout + done.stderr
    assert "discovery_server: failed for good" in done.stderr
    log = done.stderr
    # The follower is held while the server restarts: it starts only once the 10 s wait for the server is
    # over, and the server's five restarts (0.25 s to 4 s apart) usually end before that, so it never starts.
    restarting = log.index("discovery_server: restarting")
    if "follower: started" in log:
        assert restarting < log.index("warning: not ready after 10 s") < log.index("follower: started"), log
    else:
        assert "follower: final state: pending" in log, log
