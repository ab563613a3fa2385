"""E410 invalid-wheel-radius: a base's wheel_radius_m is not a length a wheel can have.

What it checks:
    When written, `wheel_radius_m` is a finite number above 0 and at most 1 (metres).

Why it matters:
    Odometry and wheel speeds are both scaled by the radius: zero divides by zero, a negative
    radius drives the base backwards, and a radius in millimetres by mistake (28 for 0.028) makes
    every Twist a thousand times too slow.

Example:
    node {
      type: DIFF_DRIVE_BASE
      wheel_radius_m: 28         # error: wheel_radius_m must be above 0 and at most 1 m, got 28
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_codegen.rules.length_range import out_of_range

CODE = "E410"
NAME = "invalid-wheel-radius"
SEVERITY = ERROR
STAGE = "check"
MAX_WHEEL_RADIUS_M = 1.0


def check(ctx):
    for view in ctx.nodes:
        problem = out_of_range(view.node, "wheel_radius_m", MAX_WHEEL_RADIUS_M, "m")
        if problem:
            yield Finding(view.at("wheel_radius_m"), problem)
