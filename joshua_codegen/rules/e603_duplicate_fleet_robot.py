"""E603 duplicate-fleet-robot: two robots of a fleet share a name or an address.

What it checks:
    No two `robot` blocks of a fleet have the same `name`, and no two the same `address`.

Why it matters:
    A robot's name names its release directory in the build, its Ansible host and its key in the fleet
    view: two robots of one name would overwrite each other. Two robots at one address would get two
    releases in turn on one machine, each replacing the other.

Example:
    fleet_config {
      robot { name: "arm_1" address: "10.0.0.11" ... }
      robot { name: "arm_2" address: "10.0.0.11" ... }   # error: arm_2 has the address of arm_1
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import robot_path
from joshua_codegen.rules.context import Finding

CODE = "E603"
NAME = "duplicate-fleet-robot"
SEVERITY = ERROR
STAGE = "fleet"


def check(ctx):
    for field in ("name", "address"):
        first: dict[str, int] = {}
        for index, robot in enumerate(ctx.fleet.robot):
            value = getattr(robot, field)
            if not value:
                continue
            if value.lower() in first:
                other = first[value.lower()]
                yield Finding(
                    robot_path(index, field),
                    f'{field} "{value}" is given to robot {ctx.fleet.robot[other].name or other + 1} already',
                    ((robot_path(other, field), "first given here"),),
                )
            else:
                first[value.lower()] = index
