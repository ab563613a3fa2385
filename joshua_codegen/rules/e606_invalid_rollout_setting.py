"""E606 invalid-rollout-setting: a fleet's rollout settings or release key path cannot be used.

What it checks:
    `rollout.batch`, when set, is at least 1; `rollout.health_timeout_s`, when set, is a finite number
    of seconds above 0; `release_key`, when set, is an absolute path (it is a path on the robots).

Why it matters:
    A batch of 0 robots would never end a rollout, a health timeout of 0 would fail every robot, and
    a relative key path would be looked up in whatever directory the rollout's SSH session starts in.

Example:
    fleet_config {
      release_key: "keys/release.pub"   # error: release_key must be an absolute path on the robots
      rollout { batch: 0 }              # error: rollout.batch must be at least 1
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import FLEET
from joshua_codegen.rules.context import Finding

CODE = "E606"
NAME = "invalid-rollout-setting"
SEVERITY = ERROR
STAGE = "fleet"


def check(ctx):
    fleet = ctx.fleet
    rollout = fleet.rollout
    if rollout.HasField("batch") and rollout.batch < 1:
        yield Finding(
            FLEET + ("rollout", "batch"), "rollout.batch must be at least 1 (robots at once after the canaries)"
        )
    if rollout.HasField("health_timeout_s") and not (
        math.isfinite(rollout.health_timeout_s) and rollout.health_timeout_s > 0
    ):
        yield Finding(
            FLEET + ("rollout", "health_timeout_s"),
            f"rollout.health_timeout_s must be a number of seconds above 0 (it is {rollout.health_timeout_s:g})",
        )
    if fleet.release_key and not fleet.release_key.startswith("/"):
        yield Finding(
            FLEET + ("release_key",),
            f'release_key "{fleet.release_key}" must be an absolute path on the robots, e.g. /etc/joshua/release.pub',
        )
