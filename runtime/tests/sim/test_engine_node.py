"""The SIMULATION node as a real process, observed by an in-process rclpy client.

The process is started the way a generated entrypoint starts it (`run_node(SETTINGS)`, SETTINGS
compiled by joshuac from a description in MODE_SIMULATION), simulating an encoder, an actuator with
a state topic, a camera and a lidar of an SO-100. The client commands the arm and checks the simulated states converge, that frames are real renders of the configured size,
that scans see the room, that every topic has the type and QoS the real node would offer, and that
SIGINT ends the process with exit code 0.
"""

import math
import signal
import time

import cv2
import numpy as np
import pytest
import sim_settings
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
from sensor_msgs.msg import CompressedImage, Image, JointState, LaserScan
from sim_ros import DISCOVERY_TIMEOUT_S, RELIABLE, SENSOR, STARTUP_TIMEOUT_S

GOAL = [0.8, 0.3, 0.2, -0.4, 1.2, 0.7]
TRACKING_TOLERANCE_RAD = 0.02
CONVERGE_TIMEOUT_S = 20.0
COMMAND_PERIOD_S = 0.1
# Standard deviation of pixel values above which a frame is a real render, not a blank fill.
MIN_PIXEL_STD = 10.0


@pytest.fixture
def arm_process(start_node):
    return start_node(
        sim_settings.simulation(
            sim_settings.ENCODER,
            sim_settings.ACTUATOR,
            sim_settings.CAMERA,
            sim_settings.WRIST_CAMERA,
            sim_settings.LIDAR,
        )
    )


def _positions(msg: JointState | None) -> list[float] | None:
    return list(msg.position) if msg is not None else None


def _converged(msg: JointState | None) -> bool:
    positions = _positions(msg)
    return positions is not None and all(abs(p - g) < TRACKING_TOLERANCE_RAD for p, g in zip(positions, GOAL))


def test_simulated_arm_camera_and_lidar(ros_client, arm_process):
    ros_client.listen("/arm/joint_states", JointState, RELIABLE)
    ros_client.listen("/arm/present", JointState, RELIABLE)
    ros_client.listen("/camera/image_raw", Image, SENSOR)
    ros_client.listen("/wrist/image/compressed", CompressedImage, SENSOR)
    ros_client.listen("/scan", LaserScan, SENSOR)
    command = ros_client.publisher("/arm/command", JointState, RELIABLE)
    topics = ("/arm/joint_states", "/arm/present", "/camera/image_raw", "/wrist/image/compressed", "/scan")
    started = ros_client.spin_until(lambda: all(ros_client.last(t) is not None for t in topics), STARTUP_TIMEOUT_S)
    assert started, f"no message on {[t for t in topics if ros_client.last(t) is None]}; {arm_process.failure()}"

    # Present states: SO-100 names, at rest near zero, efforts as fractions of the force limit.
    state = ros_client.last("/arm/joint_states")
    assert list(state.name) == sim_settings.SO100_JOINTS
    assert state.header.frame_id == "base_link"
    assert _positions(state) == pytest.approx([0.0] * 6, abs=TRACKING_TOLERANCE_RAD)
    assert len(state.velocity) == 6 and len(state.effort) == 6
    assert all(abs(e) <= 1.0 for e in state.effort)

    # Commands by name, in a different order than the node's joints, converge on both state topics.
    def send():
        msg = JointState(name=list(reversed(sim_settings.SO100_JOINTS)), position=list(reversed(GOAL)))
        command.publish(msg)

    throttle = _Throttle(COMMAND_PERIOD_S, send)
    converged = ros_client.spin_until(
        lambda: _converged(ros_client.last("/arm/joint_states")) and _converged(ros_client.last("/arm/present")),
        CONVERGE_TIMEOUT_S,
        every=throttle,
    )
    assert converged, f"states {_positions(ros_client.last('/arm/joint_states'))} did not reach {GOAL}"

    image = ros_client.last("/camera/image_raw")
    assert (image.width, image.height, image.encoding, image.step) == (320, 240, "rgb8", 960)
    assert image.header.frame_id == "camera"
    pixels = np.frombuffer(bytes(image.data), dtype=np.uint8).reshape(240, 320, 3)
    assert pixels.std() > MIN_PIXEL_STD

    # The wrist camera renders the model's "wrist" camera (its frame_id) as JPEG.
    jpeg = ros_client.last("/wrist/image/compressed")
    assert jpeg.format == "rgb8; jpeg compressed bgr8"
    assert jpeg.header.frame_id == "wrist"
    wrist = cv2.imdecode(np.frombuffer(bytes(jpeg.data), dtype=np.uint8), cv2.IMREAD_COLOR)
    assert wrist.shape == (120, 160, 3)
    assert wrist.std() > MIN_PIXEL_STD

    scan = ros_client.last("/scan")
    assert len(scan.ranges) == 360 and len(scan.intensities) == 360
    assert (scan.angle_min, scan.range_min, scan.range_max) == (0.0, pytest.approx(0.12), pytest.approx(3.5))
    assert scan.angle_increment == pytest.approx(2 * math.pi / 360)
    assert scan.scan_time == pytest.approx(0.2)
    assert scan.header.frame_id == "laser"
    assert scan.ranges[180] == pytest.approx(1.23, abs=1e-4)
    assert all(0.12 <= r <= 3.5 for r in scan.ranges)

    _assert_endpoints(ros_client)

    code, _, stderr = arm_process.stop(signal.SIGINT)
    assert code == 0, stderr
    assert "Traceback" not in stderr


class _Throttle:
    """Calls `action` at most once per `period_s`."""

    def __init__(self, period_s: float, action):
        self.period_s, self.action, self.next = period_s, action, 0.0

    def __call__(self):
        now = time.monotonic()
        if now >= self.next:
            self.next = now + self.period_s
            self.action()


def _assert_endpoints(ros_client) -> None:
    """Types and QoS of the simulated endpoints are those the real nodes declare."""
    expected = {
        "/arm/joint_states": ("sensor_msgs/msg/JointState", ReliabilityPolicy.RELIABLE),
        "/arm/present": ("sensor_msgs/msg/JointState", ReliabilityPolicy.RELIABLE),
        "/camera/image_raw": ("sensor_msgs/msg/Image", ReliabilityPolicy.BEST_EFFORT),
        "/wrist/image/compressed": ("sensor_msgs/msg/CompressedImage", ReliabilityPolicy.BEST_EFFORT),
        "/scan": ("sensor_msgs/msg/LaserScan", ReliabilityPolicy.BEST_EFFORT),
    }
    for topic, (message_type, reliability) in expected.items():
        infos = [i for i in ros_client.publishers_info(topic, DISCOVERY_TIMEOUT_S) if i.node_name == "simulation"]
        assert len(infos) == 1, topic
        assert infos[0].topic_type == message_type
        assert infos[0].qos_profile.reliability == reliability
        assert infos[0].qos_profile.durability == DurabilityPolicy.VOLATILE
    subscriptions = [
        i for i in ros_client.subscriptions_info("/arm/command", DISCOVERY_TIMEOUT_S) if i.node_name == "simulation"
    ]
    assert len(subscriptions) == 1
    assert subscriptions[0].topic_type == "sensor_msgs/msg/JointState"
    assert subscriptions[0].qos_profile.reliability == ReliabilityPolicy.RELIABLE


def test_simulated_actuator_follows_an_action_chunk_to_its_last_point(start_node, ros_client):
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    process = start_node(sim_settings.simulation(sim_settings.CHUNK_ACTUATOR))
    ros_client.listen("/arm/present", JointState, RELIABLE, keep=200)
    assert ros_client.spin_until(lambda: ros_client.last("/arm/present") is not None, STARTUP_TIMEOUT_S), (
        process.failure()
    )
    chunks = ros_client.publisher("/arm/chunks", JointTrajectory, RELIABLE)
    assert ros_client.spin_until(lambda: chunks.get_subscription_count() > 0, DISCOVERY_TIMEOUT_S)
    chunk = JointTrajectory(joint_names=["shoulder_pan", "wrist_roll"])
    chunk.header.stamp = ros_client.node.get_clock().now().to_msg()
    for i in range(5):  # 0 -> (0.8, -0.6) rad over 2 s
        offset = Duration(sec=i // 2, nanosec=(i % 2) * 500_000_000)
        chunk.points.append(JointTrajectoryPoint(positions=[0.2 * i, -0.15 * i], time_from_start=offset))
    chunks.publish(chunk)
    ros_client.spin_until(lambda: False, 1.0)
    halfway = dict(zip(ros_client.last("/arm/present").name, ros_client.last("/arm/present").position))

    def arrived() -> bool:
        present = dict(zip(ros_client.last("/arm/present").name, ros_client.last("/arm/present").position))
        return abs(present["shoulder_pan"] - 0.8) < TRACKING_TOLERANCE_RAD and abs(present["wrist_roll"] + 0.6) < (
            TRACKING_TOLERANCE_RAD
        )

    assert ros_client.spin_until(arrived, CONVERGE_TIMEOUT_S)
    # Half-way through the chunk the arm is on its way, not at the end (the goal moves along the chunk).
    assert 0.1 < halfway["shoulder_pan"] < 0.7, halfway
    code, _, stderr = process.stop(signal.SIGINT)
    assert code == 0, stderr


def test_limit_calibration_reports_the_model_ranges_and_sigterm_stops(start_node, ros_client):
    process = start_node(sim_settings.simulation(sim_settings.CALIBRATION))
    try:
        ros_client.listen("/arm/limits", JointState, RELIABLE)
        received = ros_client.spin_until(lambda: ros_client.last("/arm/limits") is not None, STARTUP_TIMEOUT_S)
        assert received, process.failure()
        limits = ros_client.last("/arm/limits")
        assert list(limits.name) == [
            "shoulder_pan.range_min",
            "shoulder_pan.range_max",
            "gripper.range_min",
            "gripper.range_max",
        ]
        # +-1.92 rad and -0.17..1.75 rad in ticks of 2 pi / 4095, the middle of each range at 2047.
        assert list(limits.position) == [796.0, 3298.0, 1936.0, 3188.0]
    finally:
        code, _, stderr = process.stop(signal.SIGTERM)
    assert code == 0, stderr
    assert "arm.json is left as it is" in stderr


@pytest.mark.parametrize(
    "overrides, unchecked, code, message",
    [
        # joshuac rejects these three (E506): they are written into the compiled settings, as a hand-edited
        # entrypoint would have them, to reach the runtime's own check.
        ([], {"model": "builtin:so101"}, 2, "simulation: error: unknown built-in simulation model 'builtin:so101'"),
        ([], {"realtime_factor": -2.0}, 2, "simulation: error: simulation realtime_factor must be >= 0, got -2.0"),
        ([], {"gl_backend": "glx"}, 2, "simulation: error: gl_backend 'glx' is not one of egl, osmesa"),
    ],
    ids=["unknown-model", "negative-realtime-factor", "unknown-gl-backend"],
)
def test_unusable_settings_exit_with_one_line(start_node, overrides, unchecked, code, message):
    settings = sim_settings.simulation(sim_settings.ENCODER, sim_settings.CAMERA, overrides=overrides)
    settings["simulation"].update(unchecked)
    returncode, stderr = start_node(settings).wait(STARTUP_TIMEOUT_S)
    assert returncode == code
    assert stderr.strip().startswith(message)
    assert len(stderr.strip().splitlines()) == 1
    assert "Traceback" not in stderr


def test_unknown_joint_exits_with_settings_error(start_node):
    """joshuac refuses such a description (E123); settings written by hand reach the engine's own check."""
    settings = sim_settings.simulation(
        sim_settings.ENCODER,
        overrides=["arm_encoder.device_ids=1,2", "arm_encoder.joint_names=shoulder_pan,wrist_flex"],
    )
    [encoder] = settings["simulation"]["simulates"]
    encoder["joint_names"] = ["shoulder_pan", "elbow"]
    returncode, stderr = start_node(settings).wait(STARTUP_TIMEOUT_S)
    assert returncode == 2
    assert "simulation: error: simulation model has no hinge or slide joint 'elbow'" in stderr
    assert "Traceback" not in stderr


def test_failing_offscreen_context_is_one_device_error(start_node):
    settings = sim_settings.simulation(sim_settings.CAMERA)
    no_egl_driver = "/nonexistent/egl_vendor.json"  # no EGL driver at all
    returncode, stderr = start_node(settings, __EGL_VENDOR_LIBRARY_FILENAMES=no_egl_driver).wait(STARTUP_TIMEOUT_S)
    assert returncode == 3
    assert stderr.strip().startswith("simulation: error: offscreen rendering with MUJOCO_GL=egl failed (")
    assert stderr.strip().endswith('try simulation gl_backend "osmesa" (Debian packages: libosmesa6)')
    assert len(stderr.strip().splitlines()) == 1
