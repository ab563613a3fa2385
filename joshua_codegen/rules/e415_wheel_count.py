"""E415 wheel-count: a differential-drive base names other than two wheel joints.

What it checks:
    A DIFF_DRIVE_BASE or MOCK_DIFF_DRIVE_BASE that sets `joint_names` sets exactly two: the left
    wheel's, then the right wheel's (default: left_wheel, right_wheel).

Why it matters:
    The base drives two wheels and publishes one joint state per wheel; any other count cannot
    name them.

Example:
    node {
      type: DIFF_DRIVE_BASE
      joint_names: ["left", "right", "caster"]   # error: a differential-drive base has 2 wheels, got 3 joint_names
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E415"
NAME = "wheel-count"
SEVERITY = ERROR
STAGE = "check"
WHEELS = len(defaults.BASE_WHEEL_JOINTS)


def check(ctx):
    for view in ctx.typed_nodes:
        node = view.node
        if node.type in defaults.BASES and node.joint_names and len(node.joint_names) != WHEELS:
            yield Finding(
                view.at("joint_names"),
                f"a differential-drive base has {WHEELS} wheels, got {len(node.joint_names)} joint_names",
            )
