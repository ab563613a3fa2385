"""E604 shared-ros-domain: two robots of a fleet would run in the same ROS domain.

What it checks:
    Every robot of a fleet, with its overrides, has its own `ros_domain_id`; two robots leaving it
    unset share the environment's domain (0 unless ROS_DOMAIN_ID says otherwise) and count as one.

Why it matters:
    Robots on one network that share a ROS domain see each other's topics: one arm's leader would
    drive every follower, one recorder would record every robot. Give each robot its own domain, e.g.
    `set: "ros_domain_id=11"` on its robot block.

Example:
    fleet_config {
      robot { name: "arm_1" description: "so100_arm.pbtxt" set: "ros_domain_id=11" ... }
      robot { name: "arm_2" description: "so100_arm.pbtxt" set: "ros_domain_id=11" ... }   # error
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import robot_path
from joshua_codegen.rules.context import Finding

CODE = "E604"
NAME = "shared-ros-domain"
SEVERITY = ERROR
STAGE = "fleet"


def _where(member) -> tuple:
    """The robot's last `set` of ros_domain_id when it has one, else its name."""
    sets = [i for i, override in enumerate(member.entry.set) if override.partition("=")[0].strip() == "ros_domain_id"]
    return robot_path(member.index, "set", sets[-1]) if sets else robot_path(member.index, "name")


def check(ctx):
    first: dict[int | None, object] = {}
    for member in ctx.members:
        config = member.config
        if config is None:
            continue
        domain = config.ros_domain_id if config.HasField("ros_domain_id") else None
        other = first.setdefault(domain, member)
        if other is member:
            continue
        shown = f"ROS domain {domain}" if domain is not None else "the environment's ROS domain (ros_domain_id unset)"
        yield Finding(
            _where(member),
            f"robot {member.entry.name} runs in {shown}, as robot {other.entry.name} does; give each robot its own "
            'ros_domain_id (e.g. set: "ros_domain_id=12")',
            ((_where(other), f"robot {other.entry.name}'s domain"),),
        )
