"""E413 invalid-command-timeout: a base's command_timeout_s would never, or always, stop the wheels.

What it checks:
    When written on a base, `command_timeout_s` is a finite number above 0 and at most 60 (seconds)
    (an arm's watchdog may be 0: E420).

Why it matters:
    The timeout stops the wheels when the Twist source dies. Zero stops them between any two
    commands; a long timeout lets a base whose teleoperation crashed drive on for minutes.

Example:
    node {
      type: DIFF_DRIVE_BASE
      command_timeout_s: 600     # error: command_timeout_s must be above 0 and at most 60 s, got 600
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_codegen.rules.length_range import out_of_range

CODE = "E413"
NAME = "invalid-command-timeout"
SEVERITY = ERROR
STAGE = "check"
MAX_COMMAND_TIMEOUT_S = 60.0


def check(ctx):
    for view in ctx.nodes:
        if view.node.type in defaults.ACTUATORS:
            continue  # an arm's watchdog may be 0 (off): E420
        problem = out_of_range(view.node, "command_timeout_s", MAX_COMMAND_TIMEOUT_S, "s")
        if problem:
            yield Finding(view.at("command_timeout_s"), problem)
