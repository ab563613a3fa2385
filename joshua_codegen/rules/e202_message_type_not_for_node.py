"""E202 message-type-not-for-node: a known message type that the node's type cannot use.

What it checks:
    Node types with fixed messages use one of them (the registry's message_types, listed in each
    message): cameras sensor_msgs/msg/Image or CompressedImage, lidars LaserScan or PointCloud2,
    encoders, DATA_SUBSCRIBER (its topic is the recorded action) and OPERATIONAL_LIMIT_CALIBRATION
    JointState; INFERENCE and actuators JointState or trajectory_msgs/msg/JointTrajectory (action
    chunks). CUSTOM takes any known type.

Why it matters:
    The node's code converts exactly these messages; any other type cannot be produced or read.

Example:
    node {
      type: LIDAR_PUBLISHER
      message_type: "sensor_msgs/msg/Image"  # error: LIDAR_PUBLISHER publishes sensor_msgs/msg/LaserScan
    }
"""

from joshua_codegen import defaults, msg_catalog
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E202"
NAME = "message-type-not-for-node"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        node = view.node
        allowed = defaults.MESSAGE_TYPES.get(node.type)
        if allowed is None or not msg_catalog.is_known(node.message_type) or node.message_type in allowed:
            continue
        verb = "publishes" if node.type in defaults.PUBLISHES_TOPIC else "subscribes to"
        yield Finding(
            view.at("message_type"),
            f"{defaults.type_name(node.type)} {verb} {' or '.join(allowed)}, not {node.message_type}",
        )
