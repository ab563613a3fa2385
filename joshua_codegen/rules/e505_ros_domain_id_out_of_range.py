"""E505 ros-domain-id-out-of-range: ros_domain_id above 232.

What it checks:
    `ros_domain_id`, when set, is between 0 and 232.

Why it matters:
    ROS 2 maps the domain id to UDP ports; above 232 the ports overflow the valid range and
    rmw refuses to start the node.

Example:
    robot_config {
      ros_domain_id: 250         # error: ros_domain_id 250 is out of range 0-232
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E505"
NAME = "ros-domain-id-out-of-range"
SEVERITY = ERROR
STAGE = "check"
MAX_ROS_DOMAIN_ID = 232


def check(ctx):
    config = ctx.config
    if config.HasField("ros_domain_id") and config.ros_domain_id > MAX_ROS_DOMAIN_ID:
        yield Finding(
            ROBOT + ("ros_domain_id",), f"ros_domain_id {config.ros_domain_id} is out of range 0-{MAX_ROS_DOMAIN_ID}"
        )
