"""E208 input-type-not-observable: a policy or recorder input carries a type it cannot read.

What it checks:
    Every `input_topics` entry of an INFERENCE or DATA_SUBSCRIBER node whose publisher is in the
    description is published as one of the types the node reads: sensor_msgs/msg/Image,
    sensor_msgs/msg/CompressedImage or sensor_msgs/msg/JointState (the node-type registry's
    input_types, as `readable_input_types` gives them). A DATA_SUBSCRIBER with output_format "mcap"
    writes a ROS bag and records any type.

Why it matters:
    Policies observe images and joint states, and datasets record them as LeRobot features; a
    LaserScan or any other type has no feature to become. The node would refuse it at start.

Example:
    node { type: LIDAR_PUBLISHER topic_name: "/scan" ... }
    node { type: DATA_SUBSCRIBER input_topics: ["/scan"] ... }   # error: /scan is a LaserScan
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.models import readable_input_types

CODE = "E208"
NAME = "input-type-not-observable"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for topic, readers in ctx.readers.items():
        publishers = [p for p in ctx.publishers.get(topic, ()) if p.message_type]
        if not publishers:
            continue
        published = publishers[0]
        for reader in readers:
            node = reader.view.node
            readable = readable_input_types(defaults.entry(node), defaults.output_format(node))
            if readable is not None and published.message_type not in readable:
                yield Finding(
                    reader.at,
                    f'{reader.view.label} cannot read "{topic}": it is published as '
                    f"{published.message_type}; inputs must be {', '.join(readable)}",
                    ((published.at, f'publisher "{published.view.name}" declared here'),),
                )
