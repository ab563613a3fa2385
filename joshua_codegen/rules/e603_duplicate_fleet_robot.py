"""E603 duplicate-fleet-robot: two robots of a fleet share a name or an address.

What it checks:
    No two `robot` blocks of a fleet have the same `name`, and no two robots the same address: a
    robot's `address`, or for a robot on several computers each of its hosts' (given in the fleet's
    `host { }` blocks, else the description's).

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


def _addresses(member):
    """(address, where it is written) of each computer of a robot: its address, or its hosts' addresses
    (given in the fleet, else the description's)."""
    if member.config is not None and member.config.host:
        given = {host.name: number for number, host in enumerate(member.entry.host)}
        for host in member.config.host:
            where = (
                robot_path(member.index, "host", given[host.name])
                if host.name in given
                else robot_path(member.index, "name")
            )
            yield host.address, where
    elif member.entry.address:
        yield member.entry.address, robot_path(member.index, "address")


def check(ctx):
    first: dict[str, tuple] = {}
    for index, robot in enumerate(ctx.fleet.robot):
        if robot.name in first:
            other = first[robot.name]
            yield Finding(
                robot_path(index, "name"),
                f'name "{robot.name}" is given to another robot already',
                ((other, "first given here"),),
            )
        elif robot.name:
            first[robot.name] = robot_path(index, "name")
    seen: dict[str, tuple] = {}
    for member in ctx.members:
        for address, where in _addresses(member):
            owner = seen.get(address.lower())
            if owner is not None and owner[0] != member.index:
                yield Finding(
                    where,
                    f'address "{address}" is given to robot {ctx.fleet.robot[owner[0]].name or owner[0] + 1} already',
                    ((owner[1], "first given here"),),
                )
            elif owner is None:
                seen[address.lower()] = (member.index, where)
