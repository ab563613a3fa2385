"""E104 missing-topic-name: a node other than CUSTOM has no topic_name.

What it checks:
    Every node except CUSTOM sets `topic_name`: the topic it publishes ({publisher_types}) or subscribes
    to ({subscriber_types}).

    Every topic a CUSTOM node declares (`publishes { ... }`, `subscribes { ... }`) sets its `topic_name`.

Why it matters:
    A node without a topic has nothing to publish or nothing to act on.

Example:
    node {
      type: CAMERA_PUBLISHER     # error: CAMERA_PUBLISHER node "camera_publisher" has no topic_name
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.node_families import TopicRole
from joshua_core.schema import robot_config_pb2 as pb

TYPE_LISTS = {
    "publisher_types": lambda entry: entry.topic == TopicRole.PUBLISHES,
    "subscriber_types": lambda entry: entry.topic == TopicRole.SUBSCRIBES,
}
CODE = "E104"
NAME = "missing-topic-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        if view.node.type != pb.CUSTOM and not view.node.topic_name:
            yield Finding(view.path, f"{view.label} has no topic_name")
    for view, holder, path in ctx.topic_holders:
        if holder is not view.node and not holder.topic_name:
            yield Finding(path, f"a topic {view.label} declares in {path[-2]} has no topic_name")
