"""The scripted demo motion: a smooth loop inside the joint ranges that moves the simulated arm."""

import signal
import subprocess
import sys

import pytest
import sim_settings
from sensor_msgs.msg import JointState
from sim_ros import RELIABLE, STARTUP_TIMEOUT_S
from sim_settings import SO100_RANGES

from joshua_runtime.sim.scripted_motion import CYCLE_S, KEYFRAMES, SO100_JOINTS, scripted_positions
from testsupport.node_process import stop_process

# Sample spacing of the smoothness check and the largest joint change allowed over it.
SAMPLE_S = 0.01
MAX_STEP_RAD = 0.05
# Seconds into the loop at which the arm is lowered over the cube (end of the second keyframe).
LOWERED_AT_S = sum(duration for duration, _ in KEYFRAMES[:2])
LOWERED_TOLERANCE_RAD = 0.05


def test_keyframes_are_reached_at_their_times():
    elapsed = 0.0
    for duration, pose in KEYFRAMES[:-1]:
        elapsed += duration
        assert scripted_positions(elapsed - 1e-9) == pytest.approx(pose, abs=1e-6)
    assert scripted_positions(0.0) == pytest.approx([0.0] * 6)  # home, the simulated arm's initial pose
    assert KEYFRAMES[-1][1] == (0.0,) * 6
    assert scripted_positions(CYCLE_S + 1.0) == pytest.approx(scripted_positions(1.0))


def test_motion_is_smooth_and_inside_the_joint_ranges():
    previous = scripted_positions(0.0)
    for i in range(1, int(CYCLE_S / SAMPLE_S) + 1):
        pose = scripted_positions(i * SAMPLE_S)
        for name, value, before in zip(SO100_JOINTS, pose, previous):
            low, high = SO100_RANGES[name]
            assert low <= value <= high
            assert abs(value - before) < MAX_STEP_RAD
        previous = pose


def test_scripted_motion_drives_the_simulated_arm(ros_env, start_node, ros_client):
    simulation = start_node(sim_settings.simulation(sim_settings.ACTUATOR)).process
    motion = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.sim.scripted_motion", "--topic", "/arm/command", "--rate-hz", "50"],
        env=ros_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        ros_client.listen("/arm/present", JointState, RELIABLE)
        ros_client.listen("/arm/command", JointState, RELIABLE)
        assert ros_client.spin_until(
            lambda: ros_client.count("/arm/present") and ros_client.count("/arm/command"), STARTUP_TIMEOUT_S
        )
        # Watch the present states for one loop: the arm must come down over the cube.
        lowered = KEYFRAMES[1][1]

        def reached_lowered_pose():
            present = list(ros_client.last("/arm/present").position)
            return all(abs(p - g) < LOWERED_TOLERANCE_RAD for p, g in zip(present[:4], lowered[:4]))

        assert ros_client.spin_until(reached_lowered_pose, CYCLE_S + LOWERED_AT_S), list(
            ros_client.last("/arm/present").position
        )
        assert list(ros_client.last("/arm/command").name) == list(SO100_JOINTS)
    finally:
        for process in (motion, simulation):
            code, _, stderr = stop_process(process, signal.SIGINT)
            assert code == 0, stderr
