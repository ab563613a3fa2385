"""Named poses of an arm (home, rest, grip_open and a description's own) and their expansion into goals.

A preset command is a name: `torque_on` and `torque_off` go to the driver as ActionPacket
preset_commands; a pose name becomes goal positions (NaN for the joints the pose leaves alone).
"""

import math

from joshua_core.schema import ActionPacket
from joshua_core.servo_topics import TORQUE_OFF, TORQUE_ON
from joshua_core.so100 import SO100_JOINTS

TORQUE_PRESETS = (TORQUE_ON, TORQUE_OFF)
# Joint poses in rad by preset name; a joint left out keeps its goal.
BUILTIN_PRESETS = {
    "home": dict.fromkeys(SO100_JOINTS, 0.0),
    "rest": {
        "shoulder_pan": 0.0,
        "shoulder_lift": -1.65,
        "elbow_flex": 1.55,
        "wrist_flex": 0.7,
        "wrist_roll": 0.0,
        "gripper": 0.0,
    },
    "grip_open": {"gripper": 1.5},
}


def poses(own: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    """The built-in poses with a description's own added (one of the same name replaces the built-in)."""
    return {**BUILTIN_PRESETS, **own}


def expand(name: str, known: dict[str, dict[str, float]], joints: list[str]) -> ActionPacket | None:
    """The ActionPacket of one preset command for a bus of `joints`; None for a name that is no preset.

    A built-in pose names SO-100 joints: on an arm without them it moves nothing (all NaN).
    """
    if name in TORQUE_PRESETS:
        return ActionPacket(preset_commands=[name])
    if name not in known:
        return None
    pose = known[name]
    return ActionPacket(position=[pose.get(joint, math.nan) for joint in joints])
