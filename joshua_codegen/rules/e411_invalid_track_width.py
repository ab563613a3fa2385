"""E411 invalid-track-width: a base's track_width_m is not a distance between two wheels.

What it checks:
    When written, `track_width_m` is a finite number above 0 and at most 5 (metres).

Why it matters:
    Turning speed is divided by the track width: zero divides by zero, a negative width turns the
    base the wrong way, and a width in millimetres by mistake makes it barely turn.

Example:
    node {
      type: DIFF_DRIVE_BASE
      track_width_m: 0           # error: track_width_m must be above 0 and at most 5 m, got 0
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_codegen.rules.length_range import out_of_range

CODE = "E411"
NAME = "invalid-track-width"
SEVERITY = ERROR
STAGE = "check"
MAX_TRACK_WIDTH_M = 5.0


def check(ctx):
    for view in ctx.nodes:
        problem = out_of_range(view.node, "track_width_m", MAX_TRACK_WIDTH_M, "m")
        if problem:
            yield Finding(view.at("track_width_m"), problem)
