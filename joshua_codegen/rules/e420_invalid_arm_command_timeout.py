"""E420 invalid-arm-command-timeout: an actuator's command_timeout_s is negative or not finite.

What it checks:
    When written, an actuator's `command_timeout_s` is a finite number of seconds, 0 or above
    (0 switches the command watchdog off, which is also the default). A base's timeout is E413.

Why it matters:
    The watchdog stops the arm when goals stop arriving; a negative or infinite timeout cannot say
    when, so the arm would never be stopped or would be stopped at once.

Example:
    node {
      type: ACTUATOR_SUBSCRIBER
      command_timeout_s: -1        # error: command_timeout_s must be 0 (off) or above, got -1
    }
"""

import math

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E420"
NAME = "invalid-arm-command-timeout"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        if view.node.type not in defaults.ACTUATORS or not view.node.HasField("command_timeout_s"):
            continue
        value = view.node.command_timeout_s
        if not math.isfinite(value):
            yield Finding(view.at("command_timeout_s"), f"command_timeout_s must be a finite number, got {value}")
        elif value < 0:
            yield Finding(view.at("command_timeout_s"), f"command_timeout_s must be 0 (off) or above, got {value:g}")
