"""E601 missing-fleet-field: a fleet lacks its name or robots, or a robot its name, description or address.

What it checks:
    A fleet file's `fleet_config` has a `name` and at least one `robot`, and every `robot` has a
    `name`, a `description` (the robot description's path, relative to the fleet file) and an
    `address` (where the rollout reaches it over SSH), unless its description has `host` blocks (then
    each computer is at its host's address). Every `host { }` of a robot has a `name` and an `address`.

Why it matters:
    The fleet's name names its Ansible group; a robot's name names its release, units and fleet key,
    its description is what it runs and its address where its releases go. Without one, nothing can be
    built or rolled out for that robot.

Example:
    fleet_config {
      name: "lab"
      robot { name: "arm_1" description: "so100_arm.pbtxt" }   # error: robot arm_1 has no address
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import FLEET, robot_path
from joshua_codegen.rules.context import Finding

CODE = "E601"
NAME = "missing-fleet-field"
SEVERITY = ERROR
STAGE = "fleet"
ROBOT_FIELDS = {
    "name": 'name: "arm_1"',
    "description": 'description: "so100_arm.pbtxt" (relative to the fleet file)',
    "address": 'address: "10.0.0.11" (where the rollout reaches it over SSH)',
}


def check(ctx):
    fleet = ctx.fleet
    if not fleet.name:
        yield Finding(FLEET, 'the fleet has no name: add name: "lab" (lower-case letters, digits and underscores)')
    if not fleet.robot:
        yield Finding(FLEET, "the fleet has no robot: add robot { name: ... description: ... address: ... }")
    for member in ctx.members:
        robot, index = member.entry, member.index
        label = f"robot {robot.name}" if robot.name else f"robot #{index + 1}"
        on_hosts = member.config is not None and len(member.config.host) > 0
        for name, example in ROBOT_FIELDS.items():
            if not getattr(robot, name) and not (name == "address" and on_hosts):
                yield Finding(robot_path(index), f"{label} has no {name}: add {example}")
        for number, host in enumerate(robot.host):
            if not host.name or not host.address:
                yield Finding(
                    robot_path(index, "host", number),
                    f'a host of {label} needs a name and an address: host {{ name: "arm" address: "10.0.0.12" }}',
                )
