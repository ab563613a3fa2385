"""E406 joint-count-mismatch: joint_names and device_ids have different lengths.

What it checks:
    When a servo node lists `joint_names`, it lists one per servo id (`device_ids`, which defaults
    to [1, 2, 3, 4, 5, 6]).

Why it matters:
    Joint names are paired with servo ids in order; a count mismatch leaves joints unnamed or
    names pointing at no servo.

Example:
    node {
      type: ACTUATOR_SUBSCRIBER
      device_ids: [1, 2, 3]
      joint_names: ["pan", "lift"]       # error: 2 joint_names for 3 servo ids
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E406"
NAME = "joint-count-mismatch"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        node = view.node
        if not node.joint_names or node.type not in defaults.FIELD_APPLIES_TO["device_ids"]:
            continue
        ids = defaults.device_ids(node)
        if len(node.joint_names) != len(ids):
            defaulted = "" if node.device_ids else f" (device_ids defaults to {ids})"
            yield Finding(
                view.at("joint_names"), f"{len(node.joint_names)} joint_names for {len(ids)} servo ids{defaulted}"
            )
