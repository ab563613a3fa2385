"""Sensor and mock nodes run as real processes, checked by an in-process rclpy client.

Each test starts a node with `run_node(SETTINGS)`, SETTINGS compiled by joshuac from a one-node
description, checks its topic name, type and QoS from the ROS graph, the values of what it
publishes, and that it exits 0 within the shutdown contract after SIGINT or SIGTERM. (DDS discovery carries reliability and durability; history and depth
are local to each endpoint and are not visible from another process.)
"""

import json
import math
import signal

import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
from sensor_msgs.msg import CompressedImage, JointState, LaserScan
from sensor_support import (
    DEFAULT_QOS,
    NODE_START_TIMEOUT_S,
    SENSOR_QOS,
    SO100_JOINTS,
    collect,
    publishers,
)

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_runtime.drivers import synthetic_room
from joshua_runtime.emulators.lds01 import Lds01Emulator
from joshua_runtime.nodes import mock_arm
from joshua_runtime.nodes.mock_camera_publisher import SCROLL_PX, gradient, pattern_frame
from testsupport.compiled_settings import compiled_node
from testsupport.joshuac_cli import ROOT
from testsupport.mjpeg_server import MjpegServer
from testsupport.node_process import SHUTDOWN_CONTRACT_S

RELIABLE_QOS = {"history": "KEEP_LAST", "depth": 3, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}


def assert_endpoint(infos, node_name: str, message_type: str, qos: dict) -> None:
    assert [info.node_name for info in infos] == [node_name]
    info = infos[0]
    assert info.topic_type == message_type
    assert info.qos_profile.reliability == ReliabilityPolicy[qos["reliability"]]
    assert info.qos_profile.durability == DurabilityPolicy[qos["durability"]]


def assert_clean_stop(node, signum) -> None:
    code, seconds, stderr = node.stop(signum)
    assert code == 0, stderr
    assert seconds < SHUTDOWN_CONTRACT_S, f"exit took {seconds:.3f} s after {signal.Signals(signum).name}"


def f32(value: float) -> float:
    return float(np.float32(value))


def lidar(port, topic: str = "/scan", frame_id: str = "laser") -> dict:
    """Settings of an LDS-01 LIDAR_PUBLISHER named "lidar" on `port`."""
    return compiled_node(
        f'name: "lidar" type: LIDAR_PUBLISHER topic_name: "{topic}" serial_port: "{port}" '
        f'baud_rate: 230400 rate_hz: 5 frame_id: "{frame_id}"'
    )


def test_mock_camera_publishes_the_moving_pattern_as_jpeg(start_node, ros_client):
    width, height = 320, 240
    settings = compiled_node(
        f'name: "mock_cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/cam/compressed" '
        'message_type: "sensor_msgs/msg/CompressedImage" '
        "qos_depth: 3 qos_reliability: RELIABLE qos_durability: TRANSIENT_LOCAL "
        f'width: {width} height: {height} rate_hz: 20 frame_id: "cam_optical"'
    )
    node = start_node(settings)
    assert_endpoint(
        publishers(ros_client, "/cam/compressed", node), "mock_cam", "sensor_msgs/msg/CompressedImage", RELIABLE_QOS
    )
    messages = collect(ros_client, CompressedImage, "/cam/compressed", RELIABLE_QOS, 3)
    import cv2

    base = gradient(width, height)
    shifts = []
    for message in messages:
        assert message.format == "jpeg" and message.header.frame_id == "cam_optical"
        frame = cv2.imdecode(np.frombuffer(bytes(message.data), np.uint8), cv2.IMREAD_COLOR)
        assert frame.shape == (height, width, 3)
        # The scroll is where blue restarts from 0; the frame must match the pattern at that scroll.
        shift = int(np.argmin(frame[height // 2, :, 0].astype(int)))
        shift -= shift % SCROLL_PX
        expected = pattern_frame(base, shift // SCROLL_PX)
        assert np.abs(frame.astype(int) - expected.astype(int)).mean() < 3
        shifts.append(shift)
    assert len(set(shifts)) == len(shifts), "the pattern does not move"
    assert_clean_stop(node, signal.SIGINT)


def test_mock_lidar_publishes_the_synthetic_room(start_node, ros_client):
    settings = compiled_node(
        'name: "mock_lidar" type: MOCK_LIDAR_PUBLISHER topic_name: "/scan" rate_hz: 10 frame_id: "laser"'
    )
    node = start_node(settings)
    assert_endpoint(publishers(ros_client, "/scan", node), "mock_lidar", "sensor_msgs/msg/LaserScan", SENSOR_QOS)
    scan = collect(ros_client, LaserScan, "/scan", SENSOR_QOS, 2)[-1]
    assert scan.header.frame_id == "laser"
    assert list(scan.ranges) == [f32(mm / 1000.0) for mm in synthetic_room.scan_mm()]
    assert (scan.ranges[0], scan.ranges[90], scan.ranges[180], scan.ranges[270]) == (f32(0.8), 1.5, 0.0, 1.0)
    assert scan.angle_increment == f32(2 * math.pi / 360) and scan.scan_time == f32(0.2)
    assert_clean_stop(node, signal.SIGTERM)


def test_mock_encoder_swings_every_joint_within_its_range(start_node, ros_client):
    names = SO100_JOINTS + ["extra_joint"]
    ids = list(range(1, len(names) + 1))  # one per joint name: the compiler holds a mock to its real type's rules
    settings = compiled_node(
        f'name: "mock_leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" '
        f"device_ids: {ids} joint_names: {json.dumps(names)} rate_hz: 50"
    )
    node = start_node(settings)
    assert_endpoint(
        publishers(ros_client, "/leader/joint_states", node), "mock_leader", "sensor_msgs/msg/JointState", DEFAULT_QOS
    )
    messages = collect(ros_client, JointState, "/leader/joint_states", DEFAULT_QOS, 10)
    for message in messages:
        assert list(message.name) == names
        assert len(message.velocity) == len(names) and list(message.effort) == [0.0] * len(names)
        for name, position in zip(names, message.position):
            low, high = mock_arm.joint_range(name)
            assert low <= position <= high, (name, position)
    first, last = messages[0].position, messages[-1].position
    assert all(a != b for a, b in zip(first, last)), "every joint moves"
    assert_clean_stop(node, signal.SIGINT)


def test_mock_actuator_follows_commands_and_publishes_its_state(start_node, ros_client):
    # Six servos by default, so the SO-100 joint names.
    settings = compiled_node(
        'name: "mock_follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/follower/command" '
        'state_topic: "/follower/state" rate_hz: 100'
    )
    node = start_node(settings)
    assert_endpoint(
        publishers(ros_client, "/follower/state", node), "mock_follower", "sensor_msgs/msg/JointState", DEFAULT_QOS
    )
    subscribers = ros_client.subscriptions_info("/follower/command", NODE_START_TIMEOUT_S)
    assert_endpoint(subscribers, "mock_follower", "sensor_msgs/msg/JointState", DEFAULT_QOS)

    commands = ros_client.publisher("/follower/command", JointState, DEFAULT_QOS)
    command = JointState(
        name=["shoulder_pan", "gripper", "not_a_joint", "elbow_flex"], position=[1.0, 5.0, 3.0, float("nan")]
    )
    expected = {"shoulder_pan": 1.0, "gripper": 1.75}
    settled = None
    for _ in range(100):
        commands.publish(command)
        state = collect(ros_client, JointState, "/follower/state", DEFAULT_QOS, 1)[0]
        present = dict(zip(state.name, state.position))
        if all(abs(present[name] - value) < 1e-3 for name, value in expected.items()):
            settled = present
            break
    assert settled is not None, f"the arm did not reach its command: {present}"
    assert list(state.name) == SO100_JOINTS
    for name in ("shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll"):
        assert settled[name] == 0.0
    assert_clean_stop(node, signal.SIGTERM)


def test_mock_actuator_follows_an_action_chunk_and_holds_its_last_point(start_node, ros_client):
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    settings = compiled_node(
        'name: "mock_follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/follower/chunks" '
        'message_type: "trajectory_msgs/msg/JointTrajectory" state_topic: "/follower/state" rate_hz: 100'
    )
    node = start_node(settings)
    subscribers = ros_client.subscriptions_info("/follower/chunks", NODE_START_TIMEOUT_S)
    assert_endpoint(subscribers, "mock_follower", "trajectory_msgs/msg/JointTrajectory", DEFAULT_QOS)
    chunks = ros_client.publisher("/follower/chunks", JointTrajectory, DEFAULT_QOS)
    ros_client.listen("/follower/state", JointState, DEFAULT_QOS, keep=400)
    chunk = JointTrajectory(joint_names=["gripper", "shoulder_pan"])
    chunk.header.stamp = ros_client.node.get_clock().now().to_msg()
    # shoulder_pan ramps 0 -> 1 rad over 1 s in five points; the gripper goes to 0.5 at once.
    for i in range(6):
        chunk.points.append(
            JointTrajectoryPoint(positions=[0.5, i / 5], time_from_start=Duration(nanosec=i * 200_000_000))
        )
    chunks.publish(chunk)
    ros_client.spin_until(lambda: False, 1.6)
    pan = [dict(zip(m.name, m.position))["shoulder_pan"] for m in ros_client.messages("/follower/state")]
    # Followed step by step: many distinct goals on the way, not five jumps, then the last point held.
    on_the_way = {round(value, 2) for value in pan if 0.05 < value < 0.95}
    assert len(on_the_way) > 20, pan
    assert all(b >= a - 1e-9 for a, b in zip(pan, pan[1:])), "a ramp never goes back"
    assert pan[-1] == pytest.approx(1.0, abs=1e-3)
    assert dict(zip(ros_client.last("/follower/state").name, ros_client.last("/follower/state").position))[
        "gripper"
    ] == pytest.approx(0.5, abs=1e-3)
    assert_clean_stop(node, signal.SIGINT)


def test_lidar_publisher_streams_emulated_turns_and_stops_the_motor(tmp_path, start_node, ros_client):
    link = tmp_path / "ttyLIDAR"
    with Lds01Emulator(link) as emulator:
        node = start_node(lidar(link, topic="/base/scan", frame_id="lidar_link"))
        assert_endpoint(publishers(ros_client, "/base/scan", node), "lidar", "sensor_msgs/msg/LaserScan", SENSOR_QOS)
        scans = collect(ros_client, LaserScan, "/base/scan", SENSOR_QOS, 2)
        for scan in scans:
            assert scan.header.frame_id == "lidar_link"
            assert (scan.ranges[0], scan.ranges[45], scan.ranges[90], scan.ranges[180], scan.ranges[270]) == (
                f32(0.8),
                f32(2.121),
                1.5,
                0.0,
                1.0,
            )
            assert scan.intensities[90] == 4000 - 1500
            assert (scan.angle_min, scan.angle_max) == (0.0, f32(2 * math.pi - 2 * math.pi / 360))
            assert (scan.range_min, scan.range_max) == (f32(0.12), 3.5)
            assert scan.time_increment == f32(1 / 1800) and scan.scan_time == f32(0.2)
        assert emulator.stream.spinning
        assert_clean_stop(node, signal.SIGTERM)
        assert not emulator.stream.spinning, "the node did not stop the motor"


def test_lidar_publisher_stops_on_sigint_too(tmp_path, start_node, ros_client):
    link = tmp_path / "ttyLIDAR"
    with Lds01Emulator(link):
        node = start_node(lidar(link))
        collect(ros_client, LaserScan, "/scan", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
        assert_clean_stop(node, signal.SIGINT)


def test_lidar_publisher_exits_3_when_the_device_disappears(tmp_path, start_node, ros_client):
    link = tmp_path / "ttyUNPLUG"
    emulator = Lds01Emulator(link).start()
    try:
        node = start_node(lidar(link))
        collect(ros_client, LaserScan, "/scan", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
    finally:
        emulator.stop()
    code, stderr = node.wait()
    assert code == 3
    ready, *rest = stderr.splitlines()  # it streamed before the device went away, so it said it was ready
    assert "]: ready: first scan published; publishing /scan" in ready
    assert rest == [stderr.splitlines()[-1]]
    assert rest[0].startswith(f"lidar: error: LDS-01 lidar at {link} stopped answering: ")


def test_lidar_publisher_exits_3_when_the_device_stops_streaming(tmp_path, start_node, ros_client):
    with Lds01Emulator(tmp_path / "ttySTALL") as emulator:
        node = start_node(lidar(emulator.link))
        collect(ros_client, LaserScan, "/scan", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
        emulator.stream.spinning = False  # the motor stalls: the port stays, the data stops
        code, stderr = node.wait()
    assert code == 3
    assert stderr.splitlines()[-1] == (
        f"lidar: error: LDS-01 lidar at {emulator.link} stopped streaming: no usable scan for {DEVICE_SILENCE_S:g} s"
    )


def test_lidar_publisher_without_its_port_exits_3_with_one_line(tmp_path, start_node):
    port = tmp_path / "ttyUSB9"
    code, stderr = start_node(lidar(port)).wait()
    assert code == 3
    assert stderr.splitlines() == [stderr.strip()]
    assert stderr.startswith(f"lidar: error: cannot open LDS-01 lidar at {port}: ")


def test_lidar_publisher_on_a_silent_device_exits_3(tmp_path, start_node):
    from joshua_runtime.emulators.pty_link import PtyLink

    with PtyLink(tmp_path / "ttySILENT") as link:
        code, stderr = start_node(lidar(link.link)).wait()
    assert code == 3
    assert (
        stderr.strip() == f"lidar: error: LDS-01 lidar at {link.link} sent no usable scan within 2 s "
        "(silent device, wrong baud rate or not an LDS-01)"
    )


def test_camera_publisher_without_its_camera_exits_3_with_one_line(start_node):
    settings = compiled_node(
        'name: "front_camera" type: CAMERA_PUBLISHER topic_name: "/front/image" camera_index: 63 frame_id: "camera"'
    )
    code, stderr = start_node(settings).wait()
    assert code == 3
    assert stderr == "front_camera: error: cannot open camera 63 (/dev/video63): no such device\n"


def network_camera(url: str) -> dict:
    return compiled_node(
        f'name: "ip_camera" type: CAMERA_PUBLISHER topic_name: "/ip/image" video_source: "{url}" '
        "width: 160 height: 120 rate_hz: 10"
    )


def test_camera_publisher_exits_3_when_its_stream_stalls(start_node, ros_client):
    from sensor_msgs.msg import Image

    with MjpegServer() as camera:
        node = start_node(network_camera(camera.url))
        collect(ros_client, Image, "/ip/image", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
        camera.stall()
        code, stderr = node.wait()
    assert code == 3, stderr
    ready, error = stderr.splitlines()  # nothing from OpenCV or FFmpeg in between
    assert "]: ready: publishing /ip/image at 10 Hz" in ready
    assert error == (
        f"ip_camera: error: video source {camera.url} stopped delivering frames: no frame for {DEVICE_SILENCE_S:g} s"
    )


def test_camera_publisher_exits_3_when_its_stream_ends(start_node, ros_client):
    from sensor_msgs.msg import Image

    with MjpegServer() as camera:
        node = start_node(network_camera(camera.url))
        collect(ros_client, Image, "/ip/image", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
        camera.end()
        code, stderr = node.wait()
    assert code == 3, stderr
    assert stderr.splitlines()[1:] == [f"ip_camera: error: video source {camera.url} stopped delivering frames"]


def test_camera_publisher_stops_at_once_while_its_stream_stalls(start_node, ros_client):
    from sensor_msgs.msg import Image

    with MjpegServer() as camera:  # a frame every 0.2 s for a node asking every 0.1 s: it always waits on one
        node = start_node(network_camera(camera.url))
        collect(ros_client, Image, "/ip/image", SENSOR_QOS, 1, timeout_s=NODE_START_TIMEOUT_S)
        camera.stall()
        ros_client.spin_until(lambda: False, 0.2)  # a read waits for the next frame, short of the watchdog
        assert_clean_stop(node, signal.SIGINT)


def test_camera_publisher_sends_640x480_frames_across_processes_without_drops(tmp_path, start_node, ros_client):
    """A video file stands in for the camera; the Fast DDS profile carries the 921,600-byte images."""
    import cv2
    from sensor_msgs.msg import Image

    from joshua_codegen.compile import compile_file
    from joshua_codegen.emitters.fastdds import IMAGES_PROFILE_PATH

    width, height, colours = 640, 480, [(0, 0, 255), (0, 255, 0), (255, 0, 0), (0, 255, 255), (255, 255, 255)]
    video = tmp_path / "clip.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 30.0, (width, height))
    for colour in colours:
        writer.write(np.full((height, width, 3), colour, np.uint8))
    writer.release()
    profile = tmp_path / IMAGES_PROFILE_PATH  # the one joshuac writes for the nodes that carry images
    profile.write_text(compile_file(str(ROOT / "config" / "robots" / "so100_arm.pbtxt")).files[IMAGES_PROFILE_PATH])
    settings = compiled_node(
        f'name: "front_camera" type: CAMERA_PUBLISHER topic_name: "/front/image" '
        f'video_source: "{video}" width: {width} height: {height} rate_hz: 30 '
        'frame_id: "front_optical"'
    )
    node = start_node(settings, FASTRTPS_DEFAULT_PROFILES_FILE=str(profile))
    assert_endpoint(publishers(ros_client, "/front/image", node), "front_camera", "sensor_msgs/msg/Image", SENSOR_QOS)
    # A deep queue on the reader side, so that only the transport could lose frames.
    deep = dict(SENSOR_QOS, depth=60)
    messages = collect(ros_client, Image, "/front/image", deep, 25)
    order = []
    for message in messages:
        assert (message.width, message.height, message.encoding, message.step) == (width, height, "bgr8", width * 3)
        assert len(message.data) == width * height * 3 and message.header.frame_id == "front_optical"
        pixels = np.frombuffer(message.data, np.uint8).reshape(height, width, 3).astype(int)
        errors = [np.abs(pixels - np.array(colour)).mean() for colour in colours]
        assert min(errors) < 3
        order.append(int(np.argmin(errors)))
    gaps = [(b - a) % len(colours) for a, b in zip(order, order[1:])]
    assert gaps == [1] * len(gaps), f"frames lost or repeated: {order}"
    assert_clean_stop(node, signal.SIGINT)
