"""E161 invalid-episode-time: a recorder's episode_time_s or reset_time_s is negative or not finite.

What it checks:
    When written, a DATA_SUBSCRIBER's `episode_time_s` and `reset_time_s` are finite numbers of
    seconds, 0 or above (0: episodes last until stopped; no reset period).

Why it matters:
    The recorder counts these down between episodes; a negative or infinite time has no meaning.

Example:
    node {
      type: DATA_SUBSCRIBER
      reset_time_s: -5               # error: reset_time_s must be 0 or above, got -5
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding, is_set

CODE = "E161"
NAME = "invalid-episode-time"
SEVERITY = ERROR
STAGE = "check"
FIELDS = ("episode_time_s", "reset_time_s")


def check(ctx):
    for view in ctx.nodes:
        for field in FIELDS:
            if not is_set(view.node, field):
                continue
            value = getattr(view.node, field)
            if not math.isfinite(value):
                yield Finding(view.at(field), f"{field} must be a finite number of seconds, got {value}")
            elif value < 0:
                yield Finding(view.at(field), f"{field} must be 0 or above, got {value:g}")
