"""E504 invalid-grace-period: a shutdown grace period that is negative, not finite, or absurdly long.

What it checks:
    `shutdown.sigint_grace_s` and `shutdown.sigterm_grace_s`, when set, are finite numbers from
    0 to 300 seconds.

Why it matters:
    The supervisor waits this long before escalating SIGINT to SIGTERM to SIGKILL; a negative
    wait is meaningless, and a very long one leaves a stuck robot running after a stop request.

Example:
    shutdown {
      sigint_grace_s: -1         # error: sigint_grace_s must be from 0 to 300 s, got -1
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E504"
NAME = "invalid-grace-period"
SEVERITY = ERROR
STAGE = "check"
MAX_GRACE_S = 300.0
FIELDS = ("sigint_grace_s", "sigterm_grace_s")


def check(ctx):
    shutdown = ctx.config.shutdown
    for field in FIELDS:
        if not shutdown.HasField(field):
            continue
        value = getattr(shutdown, field)
        if not (math.isfinite(value) and 0 <= value <= MAX_GRACE_S):
            yield Finding(ROBOT + ("shutdown", field), f"{field} must be from 0 to {MAX_GRACE_S:g} s, got {value:g}")
