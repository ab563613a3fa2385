"""E125 missing-declared-message-type: a topic a CUSTOM node declares has no message_type.

What it checks:
    Every `publishes { ... }` and `subscribes { ... }` block of a CUSTOM node sets `message_type`
    (`pkg/msg/Type`).

Why it matters:
    joshuac cannot guess what a program sends: without a type the topic cannot be checked against
    the other nodes on it (E206, E207) or shown in the manifest.

Example:
    node {
      type: CUSTOM
      executable: "/usr/bin/teleop"
      publishes { topic_name: "/cmd_vel" }   # error: topic "/cmd_vel" declared by CUSTOM node "custom" has no message_type
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E125"
NAME = "missing-declared-message-type"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view, holder, path in ctx.topic_holders:
        if holder is not view.node and holder.topic_name and not holder.message_type:
            yield Finding(
                path + ("topic_name",),
                f'topic "{holder.topic_name}" declared by {view.label} in '
                f"{path[-2]} has no message_type (e.g. geometry_msgs/msg/Twist)",
            )
