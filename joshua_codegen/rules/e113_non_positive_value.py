"""E113 non-positive-value: rate_hz, width or height is zero, negative or not finite.

What it checks:
    When written, a node's `rate_hz` is a finite number above 0, and `width` and `height` are above 0.

Why it matters:
    A zero rate would divide by zero in the timer period; a zero-sized image cannot be captured.

Example:
    node {
      type: CAMERA_PUBLISHER
      rate_hz: 0                 # error: rate_hz must be above 0, got 0
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E113"
NAME = "non-positive-value"
SEVERITY = ERROR
STAGE = "check"
FIELDS = ("rate_hz", "width", "height")


def check(ctx):
    for view in ctx.nodes:
        for field in FIELDS:
            if not view.node.HasField(field):
                continue
            value = getattr(view.node, field)
            if not math.isfinite(value):
                yield Finding(view.at(field), f"{field} must be a finite number, got {value}")
            elif value <= 0:
                yield Finding(view.at(field), f"{field} must be above 0, got {value:g}")
