"""The C++ actuator and its Python twin follow the same action chunks: same goals over time, same end, same hold.

Both follow one JointTrajectory topic on their own emulated bus. Every goal either writes, sampled while the
chunks run, must lie within the goals the shared rule (joshua_runtime.nodes.trajectory_follower) gives
between SAMPLE_LAG_S before the test asked for it and the bus's answer; a newer chunk takes over midway; a
chunk stamped before it changes nothing; once the last chunk is over both hold its last point, and the
command watchdog counts its silence from then.
"""

import copy
import signal

import numpy as np
from builtin_interfaces.msg import Duration, Time
from cpp_support import CALIBRATION, IDS, JOINTS, NODE_START_TIMEOUT_S, READER_QOS, STOP_BOUND_S, twins
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from joshua_runtime.drivers.calibration import MotorCalibration
from joshua_runtime.nodes.trajectory_follower import TrajectoryFollower, chunk_from_trajectory, now_s, ros_seconds

CONTROL_HZ = 100
COMMAND_TIMEOUT_S = 0.4
POINT_STEP_S = 0.3  # sparse points: a follower that jumped from point to point would show only a few goals
SAMPLE_LAG_S = 0.5  # a goal sampled at t was computed, and a chunk reached the nodes, at most this long late (a busy machine)
# A node follows a newer chunk from the goal it has when the chunk arrives, a little after the test sent it, so
# its first segment runs a little off the reference's, which starts at the sending: a few ticks (0.0015 rad each).
TOLERANCE_TICKS = 5
MOVING = ("shoulder_pan", "elbow_flex")
HOLD_LINE = f"no goal for {COMMAND_TIMEOUT_S:g} s: holding the present position"


def chunk(stamp_s: float, start: list[float], end: list[float], points: int) -> JointTrajectory:
    message = JointTrajectory(joint_names=list(MOVING))
    message.header.stamp = Time(sec=int(stamp_s), nanosec=int(round((stamp_s % 1) * 1e9)) % 1_000_000_000)
    for i, row in enumerate(np.linspace(start, end, points)):
        offset = i * POINT_STEP_S
        message.points.append(
            JointTrajectoryPoint(
                positions=[float(v) for v in row], time_from_start=Duration(sec=int(offset), nanosec=int(offset % 1 * 1e9))
            )
        )
    return message


def ticks(joint: str, radians: float) -> int:
    return MotorCalibration(**CALIBRATION[joint]).to_ticks(float(radians))


def test_actuators_follow_the_same_chunks_and_hold_the_last_point(buses, calibration_file, start_node, start_cpp,
                                                                    ros_client):
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    fields = (f'message_type: "trajectory_msgs/msg/JointTrajectory" rate_hz: {CONTROL_HZ} '
              f'command_timeout_s: {COMMAND_TIMEOUT_S} keep_torque_on_exit: true')
    overrides = [f"py_follower.serial_port={python_bus.link}", f"cpp_follower.serial_port={cpp_bus.link}",
                 f"py_follower.calibration_file={calibration_file}", f"cpp_follower.calibration_file={calibration_file}",
                 "py_follower.state_topic=/py/state", "cpp_follower.state_topic=/cpp/state"]
    settings, argv = twins("follower", "ACTUATOR_SUBSCRIBER", "chunks", fields, overrides)
    settings["topic"]["name"] = "/chunks"
    argv = [("topic_name:=/chunks" if arg.startswith("topic_name:=") else arg) for arg in argv]
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/py/state", JointState, READER_QOS)
    ros_client.listen("/cpp/state", JointState, READER_QOS)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp/state") and ros_client.last("/py/state"),
                                 NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    followers = ros_client.subscriptions_info("/chunks", NODE_START_TIMEOUT_S)
    assert sorted((i.node_name, i.topic_type) for i in followers) == [
        ("cpp_follower", "trajectory_msgs/msg/JointTrajectory"), ("py_follower", "trajectory_msgs/msg/JointTrajectory")]
    chunks = ros_client.publisher("/chunks", JointTrajectory, READER_QOS)
    reference = TrajectoryFollower(len(MOVING))
    in_force = []  # (from when, a copy of the reference then)
    # Where the goals a node may compute change slope: when a chunk was sent, when its points are due, and
    # when the chunk before it stops counting (expected() below).
    corners = []

    def publish(message: JointTrajectory) -> None:
        sent = now_s(ros_client.node)
        chunks.publish(message)
        accepted = chunk_from_trajectory(message, list(MOVING), sent)
        reference.accept(accepted, sent)
        in_force.append((sent, copy.deepcopy(reference)))
        corners.extend([sent, sent + SAMPLE_LAG_S, *accepted.times_s])

    def expected(at: float) -> list:
        """The goals a node may compute at `at`: the newest chunk's, and the previous chunk's while the newest may
        still be on its way to the node."""
        latest = max(i for i, (since, _) in enumerate(in_force) if since <= at)
        on_its_way = latest > 0 and at - in_force[latest][0] <= SAMPLE_LAG_S
        return [in_force[i][1].goal(at) for i in range(latest - on_its_way, latest + 1)]

    samples = {"py": [], "cpp": []}

    def sample_goals() -> None:
        for label, bus in (("py", python_bus), ("cpp", cpp_bus)):
            asked = now_s(ros_client.node)
            goal = [bus.read_register(IDS[JOINTS.index(j)], "Goal_Position") for j in MOVING]
            samples[label].append((asked, now_s(ros_client.node), goal))  # written before the answer, not long before asked

    first_stamp = now_s(ros_client.node)
    publish(chunk(first_stamp, [0.0, 0.0], [0.6, -0.5], points=5))  # 1.2 s long
    ros_client.spin_until(lambda: False, 0.6, every=sample_goals)
    second = chunk(now_s(ros_client.node), [0.9, 0.9], [-0.3, 0.2], points=4)  # first point already past on arrival
    publish(second)
    ros_client.spin_until(lambda: False, 1.2, every=sample_goals)
    stale = chunk(first_stamp + 0.1, [0.5, 0.5], [0.5, 0.5], points=6)  # stamped before the second: dropped
    chunks.publish(stale)
    ros_client.spin_until(lambda: False, 0.5, every=sample_goals)

    final = [ticks(j, v) for j, v in zip(MOVING, second.points[-1].positions)]
    for label, bus in (("py", python_bus), ("cpp", cpp_bus)):
        assert [bus.read_register(IDS[JOINTS.index(j)], "Goal_Position") for j in MOVING] == final, label
        on_the_way = {tuple(goal) for _, _, goal in samples[label]}
        assert len(on_the_way) >= 10, f"{label} jumped from point to point: {samples[label]}"
        for asked, read, goal in samples[label]:
            if asked - SAMPLE_LAG_S < in_force[0][0]:
                continue  # the first chunk may not have arrived yet
            # Goals are linear between corners: their extremes over the window lie at its ends or at a corner.
            times = [asked - SAMPLE_LAG_S, read, *(t for t in corners if asked - SAMPLE_LAG_S < t < read)]
            window = np.array([goal for t in times for goal in expected(t)])
            for column, joint in enumerate(MOVING):
                low, high = (ticks(joint, v) for v in (window[:, column].min(), window[:, column].max()))
                assert min(low, high) - TOLERANCE_TICKS <= goal[column] <= max(low, high) + TOLERANCE_TICKS, (
                    label, asked, read, joint, goal, low, high)
    assert ros_seconds(second.header.stamp) + 3 * POINT_STEP_S < now_s(ros_client.node)
    for node in (python, cpp):
        code, seconds, stderr = node.stop(signal.SIGINT)
        assert code == 0 and seconds < STOP_BOUND_S, stderr
        assert stderr.count(HOLD_LINE) == 1, stderr
        assert "action chunk dropped: stamped" in stderr, stderr
