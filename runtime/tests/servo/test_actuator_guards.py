"""The actuator's command watchdog, goal clamping and preset commands, over DDS on an emulated bus."""

import json
import signal

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_core.servo_topics import preset_topic
from joshua_runtime.drivers.calibration import uncalibrated
from testsupport.compiled_settings import compiled_node

STARTUP_TIMEOUT_S = 30.0
DATA_TIMEOUT_S = 5.0
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
SLOW_TICKS_S = 100  # Goal_Velocity that makes a long move take seconds
PAIR = 'device_ids: [1, 2] joint_names: ["pan", "gripper"] diagnostics_rate_hz: 10'


def start_actuator(start_node, ros_client, bus, extra: str = ""):
    node = start_node(
        compiled_node(
            f'name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/command" serial_port: "{bus.link}" '
            f'state_topic: "/follower/joint_states" {PAIR} {extra}'
        )
    )
    ros_client.listen("/follower/joint_states", JointState, RELIABLE)
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/follower/joint_states"), STARTUP_TIMEOUT_S), node.failure()
    return node


def diagnosis(ros_client, joint: str) -> DiagnosticStatus | None:
    message = ros_client.last("/diagnostics")
    return next((s for s in message.status if s.name == f"follower: {joint}"), None) if message else None


def test_watchdog_holds_the_present_position_then_resumes_on_the_next_goal(emulators, start_node, ros_client):
    bus = emulators("ttyWATCHHOLD", ids=[1, 2])
    node = start_actuator(start_node, ros_client, bus, "command_timeout_s: 0.5")
    command = ros_client.publisher("/follower/command", JointState, RELIABLE)
    bus.write_register(1, "Goal_Velocity", SLOW_TICKS_S)
    far = uncalibrated(1).to_radians(3500)
    command.publish(JointState(name=["pan"], position=[far]))  # one goal, 14 s away at this speed
    assert ros_client.spin_until(lambda: bus.read_register(1, "Goal_Position") == 3500, DATA_TIMEOUT_S)

    def holding():
        status = diagnosis(ros_client, "pan")
        return status is not None and "holding position" in status.message

    assert ros_client.spin_until(holding, DATA_TIMEOUT_S)
    assert diagnosis(ros_client, "pan").level == DiagnosticStatus.WARN
    stopped_at = bus.read_register(1, "Goal_Position")
    assert stopped_at < 2600 and abs(bus.position(1) - stopped_at) <= 1
    assert [bus.read_register(i, "Torque_Enable") for i in (1, 2)] == [1, 1]
    ros_client.spin_until(lambda: False, 0.5)
    assert bus.position(1) <= stopped_at + 1  # it stays where it stopped

    bus.write_register(1, "Goal_Velocity", 0)
    goal = uncalibrated(1).to_radians(2200)
    assert ros_client.spin_until(
        lambda: bus.position(1) == 2200,
        DATA_TIMEOUT_S,
        every=lambda: command.publish(JointState(name=["pan"], position=[goal])),
    )
    assert ros_client.spin_until(lambda: diagnosis(ros_client, "pan").message == "OK", DATA_TIMEOUT_S)
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    assert stderr.count("no goal for 0.5 s: holding the present position") == 1


def test_watchdog_can_release_torque_and_the_next_goal_restores_it(emulators, start_node, ros_client):
    bus = emulators("ttyWATCHFREE", ids=[1, 2])
    node = start_actuator(start_node, ros_client, bus, "command_timeout_s: 0.3 on_command_timeout: RELEASE_TORQUE")
    command = ros_client.publisher("/follower/command", JointState, RELIABLE)
    goal = JointState(name=["pan", "gripper"], position=[0.1, -0.1])
    assert ros_client.spin_until(
        lambda: bus.position(1) == uncalibrated(1).to_ticks(0.1), DATA_TIMEOUT_S, every=lambda: command.publish(goal)
    )
    released = lambda: [bus.read_register(i, "Torque_Enable") for i in (1, 2)] == [0, 0]  # noqa: E731
    assert ros_client.spin_until(released, DATA_TIMEOUT_S)
    command.publish(goal)
    assert ros_client.spin_until(
        lambda: [bus.read_register(i, "Torque_Enable") for i in (1, 2)] == [1, 1], DATA_TIMEOUT_S
    )
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    assert "no goal for 0.3 s: torque off until the next goal" in stderr


def test_goals_beyond_the_calibration_are_clamped_and_reported(emulators, start_node, ros_client, tmp_path):
    bus = emulators("ttyCLAMP", ids=[1, 2])
    limits = {"pan": (1048, 3048), "gripper": (2000, 2500)}
    calibration = {
        joint: {"id": i, "drive_mode": 0, "homing_offset": 0, "range_min": low, "range_max": high}
        for i, (joint, (low, high)) in enumerate(limits.items(), start=1)
    }
    (tmp_path / "arm.json").write_text(json.dumps(calibration))
    node = start_actuator(start_node, ros_client, bus, f'calibration_file: "{tmp_path / "arm.json"}"')
    command = ros_client.publisher("/follower/command", JointState, RELIABLE)
    message = JointState(name=["pan", "gripper"], position=[0.1, 3.0])

    def reported():
        status = diagnosis(ros_client, "gripper")
        return status is not None and status.level == DiagnosticStatus.WARN

    assert ros_client.spin_until(reported, DATA_TIMEOUT_S, every=lambda: command.publish(message))
    assert bus.read_register(2, "Goal_Position") == 2500
    gripper = diagnosis(ros_client, "gripper")
    assert "gripper goal 3.000 rad clamped to " in gripper.message  # after any load warning of the move
    assert int({item.key: item.value for item in gripper.values}["goals_clamped"]) >= 1
    assert "clamped" not in diagnosis(ros_client, "pan").message
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    assert "outside the calibrated range: gripper goal 3.000 rad clamped to" in stderr


def test_presets_over_ros_move_to_poses_and_switch_torque(emulators, start_node, ros_client):
    bus = emulators("ttyPRESET", ids=[1, 2])
    node = start_actuator(
        start_node,
        ros_client,
        bus,
        'preset { name: "wave" joint { name: "pan" position: 0.5 } } '
        'preset { name: "home" joint { name: "pan" position: -0.2 } joint { name: "gripper" '
        "position: 0.3 } }",
    )
    presets = ros_client.publisher(preset_topic("/follower/command"), String, RELIABLE)
    subscribers = ros_client.subscriptions_info(preset_topic("/follower/command"), DATA_TIMEOUT_S)
    assert [(s.node_name, s.topic_type) for s in subscribers] == [("follower", "std_msgs/msg/String")]

    def sends(name):
        return lambda: presets.publish(String(data=name))

    pan = uncalibrated(1)
    assert ros_client.spin_until(lambda: bus.position(1) == pan.to_ticks(0.5), DATA_TIMEOUT_S, every=sends("wave"))
    home = [pan.to_ticks(-0.2), uncalibrated(2).to_ticks(0.3)]  # the description's home replaces the built-in one
    assert ros_client.spin_until(
        lambda: [bus.position(1), bus.position(2)] == home, DATA_TIMEOUT_S, every=sends("home")
    )
    assert ros_client.spin_until(
        lambda: bus.position(2) == uncalibrated(2).to_ticks(1.5), DATA_TIMEOUT_S, every=sends("grip_open")
    )  # built-in
    torque = lambda: [bus.read_register(i, "Torque_Enable") for i in (1, 2)]  # noqa: E731
    assert ros_client.spin_until(lambda: torque() == [0, 0], DATA_TIMEOUT_S, every=sends("torque_off"))
    presets.publish(String(data="wave"))  # a pose moves no servo while torque is off
    ros_client.spin_until(lambda: False, 0.3)
    assert torque() == [0, 0]
    assert ros_client.spin_until(lambda: torque() == [1, 1], DATA_TIMEOUT_S, every=sends("torque_on"))
    presets.publish(String(data="dance"))
    ros_client.spin_until(lambda: False, 0.3)
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    assert "unknown preset 'dance': known are torque_on, torque_off, home, rest, grip_open, wave" in stderr


def test_a_preset_naming_an_unknown_joint_stops_the_node_in_one_line(emulators, start_node):
    bus = emulators("ttyPRESETBAD", ids=[1, 2])
    settings = compiled_node(
        f'name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/command" serial_port: "{bus.link}" {PAIR}'
    )
    settings["preset"] = [{"name": "wave", "positions": {"elbow": 0.5}}]  # written by hand, past joshuac's E422
    node = start_node(settings)
    code, stderr = node.wait(STARTUP_TIMEOUT_S)
    assert code == 2
    assert stderr == "follower: error: preset 'wave' names joint 'elbow', not one of pan, gripper\n"
