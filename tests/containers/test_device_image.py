"""The mock arm's image with its follower on a real STS3215 bus (`--set follower.type=ACTUATOR_SUBSCRIBER ...`):
the C++ actuator drives an emulated bus passed into the container, and without it preflight says so (exit 3).

A pseudo-terminal opens only through the devpts file system it lives in, so the emulated adapter is
bind-mounted at /dev/ttyUSB0 (`-v`); a real adapter is passed with `--device /dev/ttyUSB0`. Its mode
and group are set as udev sets a USB serial adapter's: 0660, group dialout, which the container's
user is in.
"""

import grp
import os

import pytest
from robot_container import exit_code, logs, median_tracking_errors, peer_samples, start, stop, wait_for_log

from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from testsupport.podman import BUILD_TIMEOUT_S

pytestmark = pytest.mark.timeout(BUILD_TIMEOUT_S)
SERIAL_PORT = "/dev/ttyUSB0"
ADAPTER_MODE = 0o660
RECORD_S = 3.0
MIN_SAMPLES = 50  # the actuator publishes present positions at 100 Hz
LAG_WINDOW_S = 0.5  # the emulated servos reach each goal within a few control ticks
TRACKING_RAD = 0.01  # median distance to a recent goal; a tick of the servo's encoder is 0.0015 rad
NODES = ("leader", "follower", "camera", "lidar")
EXIT_PREFLIGHT = 3


@pytest.fixture
def adapter(tmp_path):
    """An emulated STS3215 bus with the six SO-100 servos, looking like a USB serial adapter."""
    bus = Sts3215Emulator(tmp_path / "ttyUSB0").start()
    os.chown(bus.device_name, -1, grp.getgrnam("dialout").gr_gid)
    os.chmod(bus.device_name, ADAPTER_MODE)
    yield bus
    bus.stop()


def test_the_cpp_actuator_drives_an_emulated_bus_passed_into_the_container(
    podman, servo_arm_image, adapter, netns, containers
):
    robot = containers("servo-arm")
    timeout = int(podman.label(servo_arm_image, "io.joshua.stop-timeout"))
    start(podman, servo_arm_image, robot, netns.network_option, "-v", f"{adapter.device_name}:{SERIAL_PORT}")
    started = wait_for_log(podman, robot, "supervisor: ready: 4 of 4 nodes ready")
    assert "follower: started pid" in started and "(C++): /opt/joshua/bin/actuator_subscriber" in started, started

    samples = peer_samples(
        podman,
        servo_arm_image,
        robot,
        netns.network_option,
        ["/follower/joint_states", "/leader/joint_states"],
        RECORD_S,
    )
    follower, leader = samples["/follower/joint_states"], samples["/leader/joint_states"]
    assert len(follower) >= MIN_SAMPLES, len(follower)
    assert all(sample["name"] == list(SO100_JOINTS) for sample in follower)
    # Present positions read back from the emulated servos follow the leader's goals.
    errors = median_tracking_errors(follower, leader, LAG_WINDOW_S, clock="stamp")  # both stamp with the wall clock
    assert sorted(errors) == sorted(SO100_JOINTS) and max(errors.values()) < TRACKING_RAD, errors
    assert adapter.read_register(1, "Torque_Enable") == 1

    stop(podman, robot, timeout)
    output = logs(podman, robot)
    assert exit_code(podman, robot) == 0, output
    for node in NODES:
        assert f"{node}: final state: stopped (exited with code 0)" in output, output
    assert adapter.read_register(1, "Torque_Enable") == 0  # the actuator released the arm on SIGINT


def test_without_its_serial_adapter_the_container_ends_with_the_preflight_message(podman, servo_arm_image, containers):
    robot = containers("servo-arm")
    done = podman.run("run", "--name", robot, "--network=none", servo_arm_image, timeout=BUILD_TIMEOUT_S, check=False)
    output = done.stdout + done.stderr
    assert done.returncode == EXIT_PREFLIGHT, output
    assert f"follower: serial port {SERIAL_PORT} does not exist" in output
    assert "Traceback" not in output and "started pid" not in output
