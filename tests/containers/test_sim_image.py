"""The simulated SO-100's image (`make image CONFIG=config/robots/so100_sim.pbtxt`, its dashboard set to report to
a fleet view that is not there) runs the robot and stops it with the cascade: a ROS peer beside it sees the
simulation's joint states, `podman stop` ends it with exit 0."""

import pytest
from robot_container import exit_code, logs, median_tracking_errors, peer_samples, start, stop, wait_for_log

from joshua_core.so100 import SO100_JOINTS, SO100_RANGES
from joshua_runtime.nodes.mock_arm import BASE_PERIOD_S, PERIOD_STEP
from testsupport.podman import BUILD_TIMEOUT_S

pytestmark = pytest.mark.timeout(BUILD_TIMEOUT_S)
# A whole period of every joint's sweep (the mock leader's slowest joint takes 9 s): the simulated arm does not
# reach every pose the sweep asks for, but it follows most of the time.
RECORD_S = BASE_PERIOD_S * (1 + PERIOD_STEP * (len(SO100_JOINTS) - 1)) + 1.0
NODES = ("leader", "simulation", "dashboard")
MIN_SAMPLES = 50  # the simulation publishes joint states at 100 Hz
MOVED_RAD = 0.01  # the mock leader sweeps every joint; the simulated arm follows
LAG_WINDOW_S = 0.5  # the simulated arm lags the leader's sweep (up to 2.4 rad/s) by a fraction of this
TRACKING_RAD = 0.05  # median distance to a recent goal (measured: 0.002 to 0.009 rad)
HOLDING_EFFORT = 0.01  # N m: MuJoCo's actuators hold the arm up, where a mock actuator reports no effort
RANGE_SLACK_RAD = 0.05  # the physics may overshoot a limit a little


def test_the_simulated_arm_runs_in_its_image_beside_a_ros_peer_and_stops_with_the_cascade(
    podman, sim_image, netns, containers
):
    robot = containers("so100-sim")
    timeout = int(podman.label(sim_image, "io.joshua.stop-timeout"))
    assert timeout == 3 + 1 + 3  # the description's graces and the margin
    start(podman, sim_image, robot, netns.network_option)
    wait_for_log(podman, robot, "supervisor: ready: 3 of 3 nodes ready")

    samples = peer_samples(
        podman, sim_image, robot, netns.network_option, ["/follower/joint_states", "/leader/joint_states"], RECORD_S
    )
    follower, leader = samples["/follower/joint_states"], samples["/leader/joint_states"]
    assert len(follower) >= MIN_SAMPLES, len(follower)
    for sample in follower:
        assert sample["name"] == list(SO100_JOINTS)
        assert len(sample["velocity"]) == len(sample["effort"]) == len(SO100_JOINTS)
        for joint, position in zip(SO100_JOINTS, sample["position"]):
            low, high = SO100_RANGES[joint]
            assert low - RANGE_SLACK_RAD <= position <= high + RANGE_SLACK_RAD, (joint, position)
    first, last = follower[0]["position"], follower[-1]["position"]
    assert max(abs(a - b) for a, b in zip(first, last)) > MOVED_RAD, (first, last)
    # The simulated arm follows the leader: most of the time each joint is at a goal of the last moments.
    errors = median_tracking_errors(follower, leader, LAG_WINDOW_S)
    assert sorted(errors) == sorted(SO100_JOINTS) and max(errors.values()) < TRACKING_RAD, errors
    assert any(abs(effort) > HOLDING_EFFORT for effort in follower[-1]["effort"]), follower[-1]  # against gravity

    took = stop(podman, robot, timeout)
    output = logs(podman, robot)
    assert exit_code(podman, robot) == 0, output
    assert took < timeout, output
    assert (
        "supervisor: received SIGINT: stopping every node (SIGINT, SIGTERM after 3.0 s, SIGKILL after 1.0 s more)"
        in (output)
    )
    for node in NODES:
        assert f"{node}: final state: stopped (exited with code 0)" in output, output
    assert "escalating to" not in output, output  # every node stopped on SIGINT
