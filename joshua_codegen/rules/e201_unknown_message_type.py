"""E201 unknown-message-type: message_type is not a known ROS 2 message of the form pkg/msg/Type.

What it checks:
    A written `message_type` (of a node, or of a topic a CUSTOM node declares) has the ROS 2 form `pkg/msg/Type` and names a message of std_msgs,
    sensor_msgs, geometry_msgs, nav_msgs, diagnostic_msgs, trajectory_msgs or tf2_msgs (ROS 2 Jazzy; see
    joshua_codegen/msg_catalog.py).
    The message suggests the closest known type.

Why it matters:
    Nodes create publishers and subscriptions of this type at start-up; an unknown type fails
    only on the robot, and a misspelt one never connects to anything.

Example:
    node {
      message_type: "sensor_msgs/Image"    # error: ...; did you mean "sensor_msgs/msg/Image"?
    }
"""

from joshua_codegen import msg_catalog
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E201"
NAME = "unknown-message-type"
SEVERITY = ERROR
STAGE = "check"
PACKAGES = ", ".join(msg_catalog.PACKAGES)


def check(ctx):
    for _view, holder, path in ctx.topic_holders:
        value = holder.message_type
        if not value or msg_catalog.is_known(value):
            continue
        if msg_catalog.is_well_formed(value):
            message = f'unknown message type "{value}": joshuac knows the messages of {PACKAGES}'
        else:
            message = f'message type "{value}" is not of the form pkg/msg/Type'
        hint = msg_catalog.closest(value)
        yield Finding(path + ("message_type",), message + (f'; did you mean "{hint}"?' if hint else ""))
