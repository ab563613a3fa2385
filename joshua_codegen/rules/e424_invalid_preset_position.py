"""E424 invalid-preset-position: a preset moves one joint twice, or to a position that is not finite.

What it checks:
    Within one `preset`, each joint is listed once, and its `position` (radians) is a finite number.

Why it matters:
    Two goals for one joint leave it unclear which one the arm goes to; a NaN or infinite goal
    cannot be sent to a servo.

Example:
    preset {
      name: "wave"
      joint { name: "gripper" position: 0.2 }
      joint { name: "gripper" position: inf }   # error: gripper is listed twice in preset "wave"
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E424"
NAME = "invalid-preset-position"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        for k, preset in enumerate(view.node.preset):
            first_at = {}
            for j, joint in enumerate(preset.joint):
                if not math.isfinite(joint.position):
                    yield Finding(
                        view.at("preset", k, "joint", j, "position"),
                        f'preset "{preset.name}": {joint.name} position must be a finite number of '
                        f"radians, got {joint.position}",
                    )
                if first_at.setdefault(joint.name, j) != j:
                    yield Finding(
                        view.at("preset", k, "joint", j, "name"),
                        f'{joint.name} is listed twice in preset "{preset.name}"',
                        ((view.at("preset", k, "joint", first_at[joint.name], "name"), "first listed here"),),
                    )
