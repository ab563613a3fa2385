"""E101 invalid-robot-name: the robot name is missing or not made of lower-case letters, digits, "_".

What it checks:
    `robot_config.name` is set, starts with a lower-case letter, holds only lower-case letters,
    digits and underscores, and is at most 64 characters long.

Why it matters:
    The name becomes file and unit names (`joshua-<name>.target`, `/opt/joshua/<name>`), which
    must be portable and unambiguous.

Example:
    robot_config {
      name: "SO-100 Arm"     # error: robot name "SO-100 Arm" is invalid; e.g. "so_100_arm"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.names import MAX_ROBOT_NAME_LENGTH, ROBOT_NAME, suggested_robot_name

CODE = "E101"
NAME = "invalid-robot-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    name = ctx.config.name
    if not name:
        yield Finding(
            ROBOT + ("name",),
            'robot name is missing: add name: "my_robot" (lower-case letters, digits and underscores)',
        )
    elif len(name) > MAX_ROBOT_NAME_LENGTH:
        yield Finding(
            ROBOT + ("name",), f"robot name is {len(name)} characters long; the limit is {MAX_ROBOT_NAME_LENGTH}"
        )
    elif not ROBOT_NAME.fullmatch(name):
        hint = suggested_robot_name(name)
        message = (
            f'robot name "{name}" is invalid: use lower-case letters, digits and underscores, starting with a letter'
        )
        yield Finding(ROBOT + ("name",), message + (f'; e.g. "{hint}"' if hint else ""))
