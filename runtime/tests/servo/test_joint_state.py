"""JointState <-> PerceptionPacket / ActionPacket conversion."""

import math

from builtin_interfaces.msg import Time
from sensor_msgs.msg import JointState

from joshua_core.schema import ActionPacket, PerceptionPacket
from joshua_runtime.convert.joint_state import (
    action_to_joint_state,
    joint_state_to_action,
    joint_state_to_perception,
    perception_to_joint_state,
)


def test_perception_round_trip():
    packet = PerceptionPacket()
    packet.timestamp.seconds, packet.timestamp.nanos = 12, 345
    packet.position.name.extend(["a", "b"])
    packet.position.position.extend([0.5, -1.0])
    packet.position.velocity.extend([0.1, 0.2])
    packet.position.effort.extend([0.0, 0.3])
    message = perception_to_joint_state(packet, frame_id="base_link")
    assert (message.header.stamp.sec, message.header.stamp.nanosec) == (12, 345)
    assert message.header.frame_id == "base_link"
    assert list(message.name) == ["a", "b"]
    assert list(message.position) == [0.5, -1.0]
    back = joint_state_to_perception(message)
    assert back.position == packet.position
    assert back.timestamp == packet.timestamp


def test_unstamped_packet_takes_the_given_stamp():
    message = perception_to_joint_state(PerceptionPacket(), stamp=Time(sec=7, nanosec=8))
    assert (message.header.stamp.sec, message.header.stamp.nanosec) == (7, 8)


def test_commands_are_matched_by_name_and_missing_joints_are_nan():
    message = JointState(name=["c", "a"], position=[3.0, 1.0], velocity=[0.25, 0.5])
    action = joint_state_to_action(message, ["a", "b", "c"])
    assert action.position[0] == 1.0 and math.isnan(action.position[1]) and action.position[2] == 3.0
    assert list(action.speed) == []
    with_speed = joint_state_to_action(message, ["a", "c"], fields=("position", "velocity"))
    assert list(with_speed.speed) == [0.5, 0.25]


def test_unnamed_command_is_taken_in_bus_order():
    action = joint_state_to_action(JointState(position=[1.0, 2.0]), ["a", "b"])
    assert list(action.position) == [1.0, 2.0]


def test_action_to_joint_state():
    action = ActionPacket()
    action.position.extend([0.25, 0.5])
    action.speed.extend([1.0, 2.0])
    message = action_to_joint_state(action, ["a", "b"], frame_id="arm")
    assert list(message.name) == ["a", "b"]
    assert list(message.position) == [0.25, 0.5]
    assert list(message.velocity) == [1.0, 2.0]
    assert list(message.effort) == []
    assert message.header.frame_id == "arm"
