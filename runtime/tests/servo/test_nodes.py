"""The three STS3215 nodes as real processes on emulated buses, observed by an in-process rclpy client."""

import json
import signal

import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from servo_helpers import SO100_IDS, SO100_JOINTS, wait_for

from joshua_runtime.drivers.calibration import RADIANS_PER_TICK, load_calibration
from testsupport.compiled_settings import compiled_node

STARTUP_TIMEOUT_S = 30.0
DATA_TIMEOUT_S = 5.0
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
HAND_POSE = [1000, 1500, 2048, 2500, 3000, 3500]
UNCALIBRATED_MIDDLE = 2047.5


def test_missing_serial_port_is_one_line_and_exit_code_3(tmp_path, start_node):
    calibration = tmp_path / "calibration.json"
    nodes = []
    for node_type in ("ENCODER_PUBLISHER", "ACTUATOR_SUBSCRIBER", "OPERATIONAL_LIMIT_CALIBRATION"):
        written = f'calibration_file: "{calibration}"' if node_type == "OPERATIONAL_LIMIT_CALIBRATION" else ""
        settings = compiled_node(
            f'name: "arm" type: {node_type} topic_name: "/arm/joint_states" '
            f'serial_port: "{tmp_path / "ttyUSB9"}" {written}'
        )
        nodes.append(start_node(settings))
    for node in nodes:
        _, stderr = node.process.communicate(timeout=STARTUP_TIMEOUT_S)
        assert node.process.returncode == 3
        assert stderr == f"arm: error: serial port {tmp_path / 'ttyUSB9'} not found\n"


def test_missing_servo_is_named(emulators, start_node):
    bus = emulators("ttyFIVE", ids=[1, 2, 3, 4, 5])
    node = start_node(
        compiled_node(
            f'name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" serial_port: "{bus.link}"'
        )
    )
    _, stderr = node.process.communicate(timeout=STARTUP_TIMEOUT_S)
    assert node.process.returncode == 3
    assert stderr == f"leader: error: {bus.link}: no answer from servo id 6\n"


def test_encoder_publisher(emulators, start_node, ros_client):
    leader = emulators("ttyLEADER")
    leader.write_register(1, "Torque_Enable", 1)
    node = start_node(
        compiled_node(
            f'name: "leader_arm" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" '
            f'serial_port: "{leader.link}" frame_id: "leader_base" rate_hz: 50'
        )
    )
    ros_client.listen("/leader/joint_states", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/leader/joint_states"), STARTUP_TIMEOUT_S), node.failure()

    publishers = ros_client.publishers_info("/leader/joint_states", DATA_TIMEOUT_S)
    assert [(p.node_name, p.topic_type) for p in publishers] == [("leader_arm", "sensor_msgs/msg/JointState")]
    qos = publishers[0].qos_profile
    assert (qos.reliability, qos.durability) == (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE)
    assert leader.read_register(1, "Torque_Enable") == 0  # a leader arm is moved by hand

    for servo_id, ticks in zip(SO100_IDS, HAND_POSE):
        leader.move_by_hand(servo_id, ticks)
    expected = [(t - UNCALIBRATED_MIDDLE) * RADIANS_PER_TICK for t in HAND_POSE]

    def shows_hand_pose():
        message = ros_client.last("/leader/joint_states")
        return list(message.position) == pytest.approx(expected, abs=1e-9)

    assert ros_client.spin_until(shows_hand_pose, DATA_TIMEOUT_S)
    message = ros_client.last("/leader/joint_states")
    assert list(message.name) == SO100_JOINTS
    assert message.header.frame_id == "leader_base"
    assert len(message.velocity) == len(message.effort) == 6

    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr


def test_actuator_subscriber_drives_goals_and_publishes_state(emulators, start_node, ros_client, tmp_path):
    follower = emulators("ttyFOLLOWER")
    calibration = {
        name: {"id": i, "drive_mode": 0, "homing_offset": 0, "range_min": 1048, "range_max": 3048}
        for name, i in zip(SO100_JOINTS, SO100_IDS)
    }
    (tmp_path / "follower.json").write_text(json.dumps(calibration))
    settings = compiled_node(
        f'name: "follower_arm" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/command" '
        f'serial_port: "{follower.link}" state_topic: "/follower/joint_states" '
        f'calibration_file: "{tmp_path / "follower.json"}"'
    )
    node = start_node(settings)
    ros_client.listen("/follower/joint_states", JointState, RELIABLE)
    command = ros_client.publisher("/follower/command", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/follower/joint_states"), STARTUP_TIMEOUT_S), node.failure()
    assert [follower.read_register(i, "Torque_Enable") for i in SO100_IDS] == [1] * 6
    subscribers = ros_client.subscriptions_info("/follower/command", DATA_TIMEOUT_S)
    assert [(s.node_name, s.topic_type) for s in subscribers] == [("follower_arm", "sensor_msgs/msg/JointState")]
    assert subscribers[0].qos_profile.reliability == ReliabilityPolicy.RELIABLE

    # By name, out of order, one joint absent, one beyond the calibrated range.
    targets = {"gripper": 0.2, "shoulder_pan": -0.4, "elbow_flex": 9.0}
    message = JointState(name=list(targets), position=list(targets.values()))
    goals = {6: round(2048 + 0.2 / RADIANS_PER_TICK), 1: round(2048 - 0.4 / RADIANS_PER_TICK), 3: 3048}

    def reached():
        return all(follower.position(i) == goal for i, goal in goals.items())

    assert ros_client.spin_until(reached, DATA_TIMEOUT_S, every=lambda: command.publish(message))
    assert follower.read_register(2, "Goal_Position") == 2048  # absent joints hold still

    def state_shows_goals():
        state = ros_client.last("/follower/joint_states")
        return state.position[0] == pytest.approx(-0.4, abs=RADIANS_PER_TICK) and state.position[2] == pytest.approx(
            1000 * RADIANS_PER_TICK, abs=1e-9
        )

    assert ros_client.spin_until(state_shows_goals, DATA_TIMEOUT_S)
    assert follower.read_register(1, "Min_Position_Limit") == 1048  # calibration stored in the servos

    code, _, stderr = node.stop(signal.SIGTERM)
    assert code == 0, stderr
    assert [follower.read_register(i, "Torque_Enable") for i in SO100_IDS] == [0] * 6


def test_calibration_node_records_ranges_and_writes_lerobot_file(emulators, start_node, ros_client, tmp_path):
    arm = emulators("ttyCALIB", ids=[1, 2])
    arm.move_by_hand(1, 2500)
    arm.move_by_hand(2, 1000)
    path = tmp_path / "calibration" / "arm.json"
    settings = compiled_node(
        f'name: "calibrate" type: OPERATIONAL_LIMIT_CALIBRATION topic_name: "/arm/limits" '
        f'serial_port: "{arm.link}" device_ids: [1, 2] joint_names: ["pan", "lift"] '
        f'calibration_file: "{path}" rate_hz: 50'
    )
    node = start_node(settings)
    ros_client.listen("/arm/limits", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/arm/limits"), STARTUP_TIMEOUT_S), node.failure()
    assert arm.position(1) == 2047 and arm.position(2) == 2047  # homed at the middle pose
    assert arm.read_register(1, "Homing_Offset") == 2500 - 2047

    def published(limit: str, ticks: int) -> bool:
        message = ros_client.last("/arm/limits")
        return dict(zip(message.name, message.position)).get(limit) == ticks

    for servo_id, joint, low, high in ((1, "pan", 1200, 2900), (2, "lift", 300, 3900)):
        arm.move_by_hand(servo_id, low)
        assert ros_client.spin_until(lambda joint=joint, low=low: published(f"{joint}.range_min", low), DATA_TIMEOUT_S)
        arm.move_by_hand(servo_id, high)
        assert ros_client.spin_until(
            lambda joint=joint, high=high: published(f"{joint}.range_max", high), DATA_TIMEOUT_S
        )
        arm.move_by_hand(servo_id, 2047)
    message = ros_client.last("/arm/limits")
    assert list(message.name) == ["pan.range_min", "pan.range_max", "lift.range_min", "lift.range_max"]
    assert list(message.position) == [1200.0, 2900.0, 300.0, 3900.0]
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    saved = json.loads(path.read_text())
    assert saved == {
        "pan": {"id": 1, "drive_mode": 0, "homing_offset": 453, "range_min": 1200, "range_max": 2900},
        "lift": {"id": 2, "drive_mode": 0, "homing_offset": -1047, "range_min": 300, "range_max": 3900},
    }
    assert load_calibration(path)["lift"].middle == 2100


def test_nodes_release_the_port_and_exit_0_on_sigint(emulators, start_node):
    bus = emulators("ttyRELEASE", ids=[1])
    settings = compiled_node(
        f'name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" '
        f'serial_port: "{bus.link}" device_ids: [1] joint_names: ["j"]'
    )
    for _ in range(2):  # the second run can only open the port if the first released it
        node = start_node(settings)
        assert wait_for(lambda: bus.stats["packets"] > 5, STARTUP_TIMEOUT_S), node.failure()
        bus.stats.clear()
        code, _, stderr = node.stop(signal.SIGINT)
        assert code == 0, stderr
        assert [line for line in stderr.splitlines() if "]: ready: " not in line] == []  # nothing but its ready line


def test_encoder_rides_out_a_replug_then_exits_3_when_the_bus_stays_gone(emulators, start_node, ros_client):
    leader = emulators("ttyREPLUG", ids=[1])
    node = start_node(
        compiled_node(
            f'name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" '
            f'serial_port: "{leader.link}" device_ids: [1] joint_names: ["j"]'
        )
    )
    ros_client.listen("/leader/joint_states", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/leader/joint_states"), STARTUP_TIMEOUT_S), node.failure()

    leader.stop()
    ros_client.spin_until(lambda: False, 0.5)
    leader.move_by_hand(1, 3000)
    leader.write_register(1, "Goal_Position", 3000)
    leader.write_register(1, "Torque_Enable", 1)  # a power-cycled leader must be released again
    leader.start()
    expected = (3000 - UNCALIBRATED_MIDDLE) * RADIANS_PER_TICK

    def shows_new_position():
        return abs(ros_client.last("/leader/joint_states").position[0] - expected) < 1e-9

    assert ros_client.spin_until(shows_new_position, DATA_TIMEOUT_S)
    assert node.process.poll() is None
    assert wait_for(lambda: leader.read_register(1, "Torque_Enable") == 0, DATA_TIMEOUT_S)

    leader.stop()
    _, stderr = node.process.communicate(timeout=STARTUP_TIMEOUT_S)
    assert node.process.returncode == 3
    assert stderr.splitlines()[-1] == (
        f"leader: error: {leader.link}: bus failing for 3 s: serial port {leader.link} not found"
    )


def test_actuator_keeps_torque_on_at_exit_when_configured(emulators, start_node, ros_client):
    follower = emulators("ttyHOLD")
    settings = compiled_node(
        f'name: "holding_arm" type: ACTUATOR_SUBSCRIBER topic_name: "/hold/command" '
        f'serial_port: "{follower.link}" state_topic: "/hold/joint_states" '
        f"keep_torque_on_exit: true"
    )
    node = start_node(settings)
    ros_client.listen("/hold/joint_states", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/hold/joint_states"), STARTUP_TIMEOUT_S), node.failure()
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    assert [follower.read_register(i, "Torque_Enable") for i in SO100_IDS] == [1] * 6
