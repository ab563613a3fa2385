"""sensor_msgs/JointState <-> PerceptionPacket (joint readings) and ActionPacket (joint commands).

Commands are matched to a bus by joint name: a joint absent from a JointState becomes NaN in the
ActionPacket ("leave it alone"). A JointState without names is taken in bus order when its length
matches. Header stamps carry the packet timestamp when it has one.
"""

import math

from builtin_interfaces.msg import Time
from sensor_msgs.msg import JointState

from joshua_core.schema import ActionPacket, PerceptionPacket

NANOSECONDS_PER_SECOND = 1_000_000_000
COMMAND_FIELDS = ("position", "velocity", "effort")
# JointState field -> ActionPacket field.
ACTION_FIELD = {"position": "position", "velocity": "speed", "effort": "torque"}


def _time_from_packet(timestamp) -> Time:
    return Time(sec=timestamp.seconds, nanosec=timestamp.nanos)


def _set_packet_time(timestamp, stamp: Time) -> None:
    timestamp.seconds, timestamp.nanos = stamp.sec, stamp.nanosec


def perception_to_joint_state(packet: PerceptionPacket, stamp: Time | None = None, frame_id: str = "") -> JointState:
    """The packet's joint readings as a JointState (its timestamp, else `stamp`)."""
    message = JointState()
    if packet.HasField("timestamp"):
        message.header.stamp = _time_from_packet(packet.timestamp)
    elif stamp is not None:
        message.header.stamp = stamp
    message.header.frame_id = frame_id or packet.frame_id
    state = packet.position
    message.name = list(state.name)
    message.position = list(state.position)
    message.velocity = list(state.velocity)
    message.effort = list(state.effort)
    return message


def joint_state_to_perception(message: JointState) -> PerceptionPacket:
    packet = PerceptionPacket()
    _set_packet_time(packet.timestamp, message.header.stamp)
    packet.frame_id = message.header.frame_id
    state = packet.position
    state.name.extend(message.name)
    state.position.extend(message.position)
    state.velocity.extend(message.velocity)
    state.effort.extend(message.effort)
    return packet


def joint_state_to_action(
    message: JointState, joint_names: list[str], fields: tuple[str, ...] = ("position",)
) -> ActionPacket:
    """An ActionPacket in `joint_names` order from the chosen JointState fields (NaN where absent)."""
    action = ActionPacket()
    _set_packet_time(action.timestamp, message.header.stamp)
    if message.name:
        index = {name: i for i, name in enumerate(message.name)}
        order = [index.get(name) for name in joint_names]
    elif len(message.position) == len(joint_names):
        order = list(range(len(joint_names)))
    else:
        order = [None] * len(joint_names)
    for field in fields:
        values = list(getattr(message, field))
        if not values:
            continue
        picked = [values[i] if i is not None and i < len(values) else math.nan for i in order]
        getattr(action, ACTION_FIELD[field]).extend(picked)
    return action


def action_to_joint_state(action: ActionPacket, joint_names: list[str], frame_id: str = "") -> JointState:
    """A command JointState: positions from the packet, velocity from speed, effort from torque."""
    message = JointState()
    message.header.stamp = _time_from_packet(action.timestamp)
    message.header.frame_id = frame_id
    message.name = list(joint_names)
    message.position = list(action.position)
    message.velocity = list(action.speed)
    message.effort = list(action.torque)
    return message
