"""Descriptions of config/robots built by joshuac and run by their generated supervisor, end to end."""

import re
import signal
import subprocess
import sys

import cv2
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Image, JointState, LaserScan

from joshua_runtime.emulators.sts3215_process import Sts3215EmulatorProcess
from testsupport.joshuac_cli import ROOT, joshuac

STARTUP_TIMEOUT_S = 40.0
TRACKING_TIMEOUT_S = 15.0
# Only ends a wait for a stop that never ends. A recorder stopped before its writer has loaded LeRobot (the
# leader-follower robot is stopped seconds after its start) saves its frames first, asking the supervisor for
# more time: the import takes 3 s of CPU on an idle 2-core machine, three or four times that under load.
SHUTDOWN_TIMEOUT_S = 30.0
DISCOVERY_TIMEOUT_S = 10.0
TRACKING_TOLERANCE_TICKS = 3
SENSOR_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
RELIABLE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def wait_for_messages(ros_client, topics: list[str]) -> None:
    """Spin until a message arrived on every topic, failing with those still silent at the startup timeout."""
    heard = ros_client.spin_until(lambda: all(ros_client.last(t) is not None for t in topics), STARTUP_TIMEOUT_S)
    assert heard, f"no message on {[t for t in topics if ros_client.last(t) is None]}"


def build(config: str, out, *overrides: str) -> None:
    args = [arg for override in overrides for arg in ("--set", override)]
    result = joshuac("build", ROOT / "config" / "robots" / config, "-o", out, *args)
    assert result.returncode == 0, result.stderr


def start_supervisor(out, env) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, str(out / "supervisor.py")],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


def stop(supervisor: subprocess.Popen) -> tuple[int, str]:
    supervisor.send_signal(signal.SIGINT)
    try:
        output, _ = supervisor.communicate(timeout=SHUTDOWN_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        supervisor.kill()
        output, _ = supervisor.communicate()
        pytest.fail(f"supervisor did not stop within {SHUTDOWN_TIMEOUT_S} s:\n{output}")
    return supervisor.returncode, output


def test_mock_robot_publishes_every_topic_with_its_declared_types_and_qos(tmp_path, ros_env, ros_client):
    out = tmp_path / "out"
    build("mock_arm.pbtxt", out)
    supervisor = start_supervisor(out, ros_env)
    try:
        ros_client.listen("/camera/image_raw", Image, SENSOR_QOS)
        ros_client.listen("/scan", LaserScan, SENSOR_QOS)
        ros_client.listen("/leader/joint_states", JointState, RELIABLE_QOS)
        ros_client.listen("/follower/joint_states", JointState, RELIABLE_QOS)
        wait_for_messages(ros_client, ["/camera/image_raw", "/scan", "/leader/joint_states", "/follower/joint_states"])
        image = ros_client.last("/camera/image_raw")
        assert (image.width, image.height) == (320, 240)
        assert len(ros_client.last("/scan").ranges) == 360
        leader = ros_client.last("/leader/joint_states")
        assert list(leader.name) == [
            "shoulder_pan",
            "shoulder_lift",
            "elbow_flex",
            "wrist_flex",
            "wrist_roll",
            "gripper",
        ]
        camera = ros_client.publishers_info("/camera/image_raw", DISCOVERY_TIMEOUT_S)
        assert [(i.node_name, i.topic_type, i.qos_profile.reliability, i.qos_profile.durability) for i in camera] == [
            ("camera", "sensor_msgs/msg/Image", ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE)
        ]
        follower = ros_client.publishers_info("/follower/joint_states", DISCOVERY_TIMEOUT_S)
        assert [(i.node_name, i.qos_profile.reliability) for i in follower] == [
            ("follower", ReliabilityPolicy.RELIABLE)
        ]
    finally:
        code, output = stop(supervisor)
    assert code == 0, output
    for node in ("leader", "follower", "camera", "lidar"):
        assert re.search(rf"^\[ *[0-9.]+\] {node}: pid [0-9]+ exited with code 0 ", output, re.M), output


def write_video(path, frames: int = 30) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 30, (320, 240))
    for i in range(frames):
        frame = np.full((240, 320, 3), (i * 8) % 256, dtype=np.uint8)
        cv2.rectangle(frame, (10 + i * 5, 60), (60 + i * 5, 120), (0, 0, 255), -1)
        writer.write(frame)
    writer.release()


def test_leader_follower_description_teleoperates_emulated_buses(tmp_path, ros_env, ros_client):
    leader_bus = Sts3215EmulatorProcess(tmp_path / "ttyLEADER").start()  # answers whatever this process runs
    follower_bus = Sts3215EmulatorProcess(tmp_path / "ttyFOLLOWER").start()
    video = tmp_path / "camera.avi"
    write_video(video)
    out = tmp_path / "out"
    build(
        "so100_leader_follower.pbtxt",
        out,
        f"encoder_publisher.serial_port={leader_bus.link}",
        f"actuator_subscriber.serial_port={follower_bus.link}",
        f"camera_publisher.video_source={video}",
        f"data_subscriber.output_directory={tmp_path / 'episodes'}",
        f"cpp_bin_dir={tmp_path / 'bin'}",
    )
    supervisor = start_supervisor(out, ros_env)
    try:
        ros_client.listen("/leader/joint_states", JointState, RELIABLE_QOS)
        ros_client.listen("/camera/image_raw", Image, SENSOR_QOS)
        wait_for_messages(ros_client, ["/leader/joint_states", "/camera/image_raw"])
        pose = {1: 1500, 2: 2500, 3: 1800, 4: 2300, 5: 1000, 6: 2600}
        for servo_id, ticks in pose.items():
            leader_bus.move_by_hand(servo_id, ticks)

        def follower_tracks() -> bool:
            return all(abs(follower_bus.position(i) - ticks) <= TRACKING_TOLERANCE_TICKS for i, ticks in pose.items())

        assert follower_bus.wait_until(follower_tracks, TRACKING_TIMEOUT_S), {i: follower_bus.position(i) for i in pose}
    finally:
        code, output = stop(supervisor)
        leader_bus.stop()
        follower_bus.stop()
    assert code == 0, output
    assert "C++ binary" in output  # CPP preferred, no binary in cpp_bin_dir: the Python fallback is logged
    assert follower_bus.read_register(1, "Torque_Enable") == 0  # released on shutdown
