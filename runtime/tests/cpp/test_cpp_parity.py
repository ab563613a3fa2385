"""The C++ nodes against their Python twins: same emulator state in, same messages, QoS and registers out.

Each test compiles one description with a Python node and a C++ node of the same type (on their own
emulated device and topic), runs both over real DDS, and compares what they publish and what they
leave on the bus. The C++ binary gets the command line the generated supervisor gives it.
"""

import signal

import numpy as np
import pytest
from cpp_support import (
    CALIBRATION,
    IDS,
    JOINTS,
    MESSAGE_TIMEOUT_S,
    NODE_START_TIMEOUT_S,
    POSES,
    READER_QOS,
    STOP_BOUND_S,
    twins,
)
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState, LaserScan, PointCloud2

from joshua_runtime.drivers.calibration import MotorCalibration

SENSOR_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)


def endpoint_qos(infos) -> list:
    return [(info.topic_type, info.qos_profile.reliability, info.qos_profile.durability) for info in infos]


def same_joint_states(python: JointState | None, cpp: JointState | None) -> bool:
    """Same frame, joint names, positions, velocities and efforts (to 1e-12)."""
    if python is None or cpp is None or list(python.name) != JOINTS or list(cpp.name) != JOINTS:
        return False
    return python.header.frame_id == cpp.header.frame_id and all(
        list(getattr(cpp, field)) == pytest.approx(list(getattr(python, field)), abs=1e-12)
        for field in ("position", "velocity", "effort"))


def assert_twins_agree(ros_client, python_topic: str, cpp_topic: str) -> None:
    """Both nodes come to publish the same JointState (readings of the same, settled emulator state)."""

    def agree() -> bool:
        return same_joint_states(ros_client.last(python_topic), ros_client.last(cpp_topic))

    assert ros_client.spin_until(agree, MESSAGE_TIMEOUT_S), (ros_client.last(python_topic), ros_client.last(cpp_topic))


def stop_both(python, cpp, signum) -> None:
    for node in (python, cpp):
        code, seconds, stderr = node.stop(signum)
        assert code == 0, stderr
        assert seconds < STOP_BOUND_S


def test_encoders_publish_the_same_calibrated_joint_states(buses, calibration_file, start_node, start_cpp,
                                                           ros_client):
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    fields = ('qos_reliability: RELIABLE qos_durability: TRANSIENT_LOCAL qos_depth: 3 rate_hz: 50 '
              'frame_id: "arm_base"')
    settings, argv = twins("leader", "ENCODER_PUBLISHER", "joint_states", fields, [
        f"py_leader.serial_port={python_bus.link}", f"cpp_leader.serial_port={cpp_bus.link}",
        f"py_leader.calibration_file={calibration_file}", f"cpp_leader.calibration_file={calibration_file}"])
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/py/joint_states", JointState, READER_QOS)
    ros_client.listen("/cpp/joint_states", JointState, READER_QOS)

    for pose in POSES:
        for bus in (python_bus, cpp_bus):
            for servo_id, ticks in zip(IDS, pose):
                bus.move_by_hand(servo_id, ticks)

        def both_show_pose() -> bool:
            present = [cpp_bus.read_register(i, "Present_Position") for i in IDS]
            expected = [MotorCalibration(**CALIBRATION[n]).to_radians(t) for n, t in zip(JOINTS, present)]
            messages = [ros_client.last(t) for t in ("/py/joint_states", "/cpp/joint_states")]
            return all(m is not None and list(m.position) == pytest.approx(expected, abs=1e-12) for m in messages)

        assert ros_client.spin_until(both_show_pose, NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
        assert_twins_agree(ros_client, "/py/joint_states", "/cpp/joint_states")
        assert ros_client.last("/cpp/joint_states").header.frame_id == "arm_base"

    python_info = ros_client.publishers_info("/py/joint_states", MESSAGE_TIMEOUT_S)
    cpp_info = ros_client.publishers_info("/cpp/joint_states", MESSAGE_TIMEOUT_S)
    assert [info.node_name for info in cpp_info] == ["cpp_leader"]
    assert endpoint_qos(cpp_info) == endpoint_qos(python_info) == [
        ("sensor_msgs/msg/JointState", ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL)]
    for register in ("Homing_Offset", "Min_Position_Limit", "Max_Position_Limit", "Torque_Enable"):
        assert [cpp_bus.read_register(i, register) for i in IDS] == [python_bus.read_register(i, register) for i in IDS]
    assert [cpp_bus.read_register(i, "Homing_Offset") for i in IDS] == [CALIBRATION[n]["homing_offset"] for n in JOINTS]
    stop_both(python, cpp, signal.SIGTERM)


def test_actuators_write_the_same_goals_and_report_the_same_state(buses, calibration_file, start_node, start_cpp,
                                                                   ros_client):
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    fields = 'rate_hz: 50 frame_id: "follower_base" keep_torque_on_exit: true'
    overrides = [f"py_follower.serial_port={python_bus.link}", f"cpp_follower.serial_port={cpp_bus.link}",
                 f"py_follower.calibration_file={calibration_file}", f"cpp_follower.calibration_file={calibration_file}",
                 "py_follower.state_topic=/py/state", "cpp_follower.state_topic=/cpp/state"]
    settings, argv = twins("follower", "ACTUATOR_SUBSCRIBER", "command", fields, overrides)
    # Both follow one command topic.
    settings["topic"]["name"] = "/command"
    argv = [("topic_name:=/command" if arg.startswith("topic_name:=") else arg) for arg in argv]
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/py/state", JointState, READER_QOS)
    ros_client.listen("/cpp/state", JointState, READER_QOS)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp/state") and ros_client.last("/py/state"),
                                 NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    followers = ros_client.subscriptions_info("/command", MESSAGE_TIMEOUT_S)
    assert sorted(info.node_name for info in followers) == ["cpp_follower", "py_follower"]
    assert len({(info.qos_profile.reliability, info.qos_profile.durability) for info in followers}) == 1
    assert [cpp_bus.read_register(i, "Torque_Enable") for i in IDS] == [1] * 6

    commands = ros_client.publisher("/command", JointState, READER_QOS)
    # By name, a subset with a joint far out of its range and an unknown name; then in bus order, without names.
    named = JointState(name=["gripper", "elbow_flex", "nonexistent", "shoulder_pan"], position=[0.4, -0.3, 1.0, 9.0])
    unnamed = JointState(position=[0.1, -0.2, 0.3, -0.4, 0.5, -0.6])
    for command in (named, unnamed):
        before = [cpp_bus.read_register(i, "Goal_Position") for i in IDS]

        def goals_arrived(command=command, before=before) -> bool:
            commands.publish(command)
            goals = [[bus.read_register(i, "Goal_Position") for i in IDS] for bus in (python_bus, cpp_bus)]
            return goals[0] == goals[1] != before

        assert ros_client.spin_until(goals_arrived, MESSAGE_TIMEOUT_S), (python.failure(), cpp.failure())
        if command is named:  # 9 rad is far past shoulder_pan's range: clamped to its end
            assert cpp_bus.read_register(1, "Goal_Position") == CALIBRATION["shoulder_pan"]["range_max"]
        assert python_bus.wait_until(lambda: all(python_bus.position(i) == python_bus.read_register(i, "Goal_Position")
                                                 for i in IDS), MESSAGE_TIMEOUT_S)
        assert cpp_bus.wait_until(lambda: all(cpp_bus.position(i) == cpp_bus.read_register(i, "Goal_Position")
                                              for i in IDS), MESSAGE_TIMEOUT_S)
        assert_twins_agree(ros_client, "/py/state", "/cpp/state")
        assert ros_client.last("/cpp/state").header.frame_id == "follower_base"

    stop_both(python, cpp, signal.SIGINT)
    # keep_torque_on_exit: both leave the arm holding its pose.
    assert [cpp_bus.read_register(i, "Torque_Enable") for i in IDS] == [1] * 6
    assert [python_bus.read_register(i, "Torque_Enable") for i in IDS] == [1] * 6


def test_lidars_publish_the_same_scans(lidars, start_node, start_cpp, ros_client):
    python_lidar, cpp_lidar = lidars("ttyPY"), lidars("ttyCPP")
    fields = 'frame_id: "base_scan"'
    settings, argv = twins("lidar", "LIDAR_PUBLISHER", "scan", fields, [
        f"py_lidar.serial_port={python_lidar.link}", f"cpp_lidar.serial_port={cpp_lidar.link}"])
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/py/scan", LaserScan, SENSOR_QOS)
    ros_client.listen("/cpp/scan", LaserScan, SENSOR_QOS)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp/scan") and ros_client.last("/py/scan"),
                                 NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    python_scan, cpp_scan = ros_client.last("/py/scan"), ros_client.last("/cpp/scan")
    assert cpp_scan.header.frame_id == python_scan.header.frame_id == "base_scan"
    for field in ("angle_min", "angle_max", "angle_increment", "range_min", "range_max", "time_increment",
                  "scan_time"):
        assert getattr(cpp_scan, field) == getattr(python_scan, field), field
    assert list(cpp_scan.ranges) == list(python_scan.ranges)
    assert list(cpp_scan.intensities) == list(python_scan.intensities)
    assert len(cpp_scan.ranges) == 360 and any(cpp_scan.ranges)
    python_info = ros_client.publishers_info("/py/scan", MESSAGE_TIMEOUT_S)
    cpp_info = ros_client.publishers_info("/cpp/scan", MESSAGE_TIMEOUT_S)
    assert endpoint_qos(cpp_info) == endpoint_qos(python_info) == [
        ("sensor_msgs/msg/LaserScan", ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE)]
    stop_both(python, cpp, signal.SIGINT)


def test_lidars_publish_the_same_point_clouds(lidars, start_node, start_cpp, ros_client):
    python_lidar, cpp_lidar = lidars("ttyPY"), lidars("ttyCPP")
    fields = 'frame_id: "base_scan" message_type: "sensor_msgs/msg/PointCloud2"'
    settings, argv = twins("lidar", "LIDAR_PUBLISHER", "points", fields, [
        f"py_lidar.serial_port={python_lidar.link}", f"cpp_lidar.serial_port={cpp_lidar.link}"])
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/py/points", PointCloud2, SENSOR_QOS)
    ros_client.listen("/cpp/points", PointCloud2, SENSOR_QOS)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp/points") and ros_client.last("/py/points"),
                                 NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    python_cloud, cpp_cloud = ros_client.last("/py/points"), ros_client.last("/cpp/points")
    assert cpp_cloud.header.frame_id == python_cloud.header.frame_id == "base_scan"
    for field in ("height", "width", "is_bigendian", "point_step", "row_step", "is_dense"):
        assert getattr(cpp_cloud, field) == getattr(python_cloud, field), field
    assert [(f.name, f.offset, f.datatype, f.count) for f in cpp_cloud.fields] == [
        (f.name, f.offset, f.datatype, f.count) for f in python_cloud.fields]
    assert cpp_cloud.width > 0
    # The emulators turn the same room: the same points, to float32 rounding of cos/sin.
    points = [np.frombuffer(bytes(c.data), dtype="<f4").reshape(-1, 4) for c in (python_cloud, cpp_cloud)]
    assert np.allclose(points[0], points[1], rtol=0, atol=1e-6)
    python_info = ros_client.publishers_info("/py/points", MESSAGE_TIMEOUT_S)
    cpp_info = ros_client.publishers_info("/cpp/points", MESSAGE_TIMEOUT_S)
    assert endpoint_qos(cpp_info) == endpoint_qos(python_info) == [
        ("sensor_msgs/msg/PointCloud2", ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE)]
    stop_both(python, cpp, signal.SIGINT)
