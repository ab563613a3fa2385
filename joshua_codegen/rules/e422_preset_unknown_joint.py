"""E422 preset-unknown-joint: a preset names a joint the node does not have.

What it checks:
    Every `joint { name }` of a node's `preset` is one of the node's joint names (its
    `joint_names`, or the SO-100 names by default for six servos).

Why it matters:
    A preset is sent to the servos by joint name; a misspelt joint would be left where it is while
    the others move, which on an arm can mean a collision.

Example:
    node {
      type: ACTUATOR_SUBSCRIBER
      preset { name: "wave" joint { name: "elbow" position: 0.5 } }   # error: the SO-100 joint is elbow_flex
    }
"""

import difflib

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E422"
NAME = "preset-unknown-joint"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        if not view.node.preset:
            continue
        joints = defaults.joint_names(view.node)
        for k, preset in enumerate(view.node.preset):
            for j, joint in enumerate(preset.joint):
                if joint.name in joints:
                    continue
                close = difflib.get_close_matches(joint.name, joints, n=1)
                hint = f'; did you mean "{close[0]}"?' if close else f" (its joints: {', '.join(joints)})"
                yield Finding(
                    view.at("preset", k, "joint", j, "name"),
                    f'preset "{preset.name}" names joint "{joint.name}", which node "{view.name}" does not have{hint}',
                )
