"""E423 invalid-preset-name: a preset's name is empty, repeated, reserved or not one word.

What it checks:
    Every `preset` of a node has a name made of letters, digits, `_` and `-`, unique in the node,
    and other than the torque commands `torque_on` and `torque_off`.

Why it matters:
    A preset is called by its name on `<topic_name>/preset` (std_msgs/String); an empty or repeated
    name cannot be called, and a torque command's name cannot be a pose.

Example:
    node {
      type: ACTUATOR_SUBSCRIBER
      preset { name: "torque_off" joint { name: "gripper" position: 0 } }   # error: reserved name
    }
"""

import re

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.servo_topics import TORQUE_OFF, TORQUE_ON

CODE = "E423"
NAME = "invalid-preset-name"
SEVERITY = ERROR
STAGE = "check"
_WORD = re.compile(r"[A-Za-z0-9_-]+")


def check(ctx):
    for view in ctx.nodes:
        first_at = {}
        for k, preset in enumerate(view.node.preset):
            at = view.at("preset", k, "name")
            if not preset.name:
                yield Finding(view.at("preset", k), "preset has no name")
            elif preset.name in (TORQUE_ON, TORQUE_OFF):
                yield Finding(at, f'preset name "{preset.name}" is reserved for the torque command')
            elif not _WORD.fullmatch(preset.name):
                yield Finding(at, f'preset name "{preset.name}" must be letters, digits, "_" or "-"')
            elif first_at.setdefault(preset.name, k) != k:
                yield Finding(
                    at,
                    f'preset "{preset.name}" is defined twice',
                    ((view.at("preset", first_at[preset.name], "name"), "first defined here"),),
                )
