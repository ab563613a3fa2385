"""E602 invalid-fleet-name: a fleet's or a fleet robot's name is not lower-case letters, digits and "_".

What it checks:
    `fleet_config.name` and every robot's `name` start with a lower-case letter, hold only
    lower-case letters, digits and underscores, and are at most 64 characters long (as robot names).

Why it matters:
    A fleet robot's name replaces its description's robot name: it names the robot's units
    (`joshua-<name>.target`), its control socket, its host in the Ansible inventory and its key in the
    fleet view (`joshua/<name>/...`). The fleet's name is its Ansible group.

Example:
    fleet_config {
      name: "lab"
      robot { name: "arm-1" ... }   # error: robot name "arm-1" is invalid; e.g. "arm_1"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import FLEET, robot_path
from joshua_codegen.rules.context import Finding
from joshua_core.names import MAX_ROBOT_NAME_LENGTH, is_robot_name, suggested_robot_name

CODE = "E602"
NAME = "invalid-fleet-name"
SEVERITY = ERROR
STAGE = "fleet"


def _problem(what: str, name: str) -> str:
    hint = suggested_robot_name(name)
    message = f'{what} "{name}" is invalid: use lower-case letters, digits and underscores, starting with a letter'
    message += f", at most {MAX_ROBOT_NAME_LENGTH} characters"
    return message + (f'; e.g. "{hint}"' if hint and hint != name else "")


def check(ctx):
    if ctx.fleet.name and not is_robot_name(ctx.fleet.name):
        yield Finding(FLEET + ("name",), _problem("fleet name", ctx.fleet.name))
    for index, robot in enumerate(ctx.fleet.robot):
        if robot.name and not is_robot_name(robot.name):
            yield Finding(robot_path(index, "name"), _problem("robot name", robot.name))
