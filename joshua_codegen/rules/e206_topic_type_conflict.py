"""E206 topic-type-conflict: one topic is published with two message types.

What it checks:
    All publishers of a topic (topic_name of publishers and INFERENCE, state_topic of actuators)
    use one message type. The error is at each publisher whose type differs from the first one.

Why it matters:
    ROS 2 topics carry one type; subscribers of either type would miss the other publisher's data.

Example:
    node { type: ENCODER_PUBLISHER topic_name: "/arm" ... }
    node { type: CAMERA_PUBLISHER topic_name: "/arm" }   # error: "/arm" is published as sensor_msgs/msg/Image here
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E206"
NAME = "topic-type-conflict"
SEVERITY = ERROR
STAGE = "check"


def _type_field(ctx, endpoint):
    path = endpoint.at[:-1] + ("message_type",)
    if endpoint.at[-1] == "topic_name" and ctx.written(path):
        return path
    return endpoint.at


def check(ctx):
    for topic, publishers in ctx.publishers.items():
        typed = [p for p in publishers if p.message_type]
        if not typed:
            continue
        first = typed[0]
        for other in typed[1:]:
            if other.message_type != first.message_type:
                yield Finding(
                    _type_field(ctx, other),
                    f'"{topic}" is published here as {other.message_type}, but node '
                    f'"{first.view.name}" publishes it as {first.message_type}',
                    ((_type_field(ctx, first), "other publisher declared here"),),
                )
