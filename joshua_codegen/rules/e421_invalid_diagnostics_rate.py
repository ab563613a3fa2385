"""E421 invalid-diagnostics-rate: diagnostics_rate_hz is zero, negative or not finite.

What it checks:
    When written, a servo node's `diagnostics_rate_hz` (how often it publishes /diagnostics,
    default 1 Hz) is a finite number above 0.

Why it matters:
    The rate sets the period of the node's health reports; zero would divide by zero, and an
    infinite rate would read servo status on every spin and starve the control loop.

Example:
    node {
      type: ENCODER_PUBLISHER
      diagnostics_rate_hz: 0       # error: diagnostics_rate_hz must be above 0, got 0
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E421"
NAME = "invalid-diagnostics-rate"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        if not view.node.HasField("diagnostics_rate_hz"):
            continue
        value = view.node.diagnostics_rate_hz
        if not math.isfinite(value):
            yield Finding(view.at("diagnostics_rate_hz"), f"diagnostics_rate_hz must be a finite number, got {value}")
        elif value <= 0:
            yield Finding(view.at("diagnostics_rate_hz"), f"diagnostics_rate_hz must be above 0, got {value:g}")
