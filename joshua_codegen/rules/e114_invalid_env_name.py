"""E114 invalid-env-name: an env key that is not a valid environment variable name.

What it checks:
    Keys of the robot's and each node's `env` map match [A-Za-z_][A-Za-z0-9_]*.

Why it matters:
    Environment names go into systemd units, supervisord sections and the supervisor; a name
    with "=", spaces or a leading digit cannot be set (or sets something else).

Example:
    env { key: "ROS-DOMAIN" value: "3" }     # error: env name "ROS-DOMAIN" is invalid
"""

import re

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E114"
NAME = "invalid-env-name"
SEVERITY = ERROR
STAGE = "check"
ENV_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _bad(env, base):
    for key in sorted(env):
        if not ENV_NAME.fullmatch(key):
            yield Finding(
                base + ("env", key),
                f'env name "{key}" is invalid: use letters, digits and "_", not starting with a digit',
            )


def check(ctx):
    yield from _bad(ctx.config.env, ROBOT)
    for view in ctx.nodes:
        yield from _bad(view.node.env, view.path)
