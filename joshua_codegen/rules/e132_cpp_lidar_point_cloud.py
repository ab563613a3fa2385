"""E132 cpp-lidar-point-cloud: a lidar asks for PointCloud2 from the C++ implementation.

What it checks:
    A LIDAR_PUBLISHER with `preferred_backend: CPP` keeps the default message_type
    (sensor_msgs/msg/LaserScan). In MODE_SIMULATION no C++ node runs, so any type is fine there.

Why it matters:
    The C++ lidar node publishes LaserScan only; point clouds come from the Python implementation,
    so subscribers expecting PointCloud2 would find another type on the topic.

Example:
    node {
      type: LIDAR_PUBLISHER topic_name: "/points" serial_port: "/dev/ttyUSB0"
      message_type: "sensor_msgs/msg/PointCloud2"
      preferred_backend: CPP        # error: the C++ LIDAR_PUBLISHER publishes LaserScan only
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E132"
NAME = "cpp-lidar-point-cloud"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    if ctx.config.mode == pb.MODE_SIMULATION:
        return
    for view in ctx.typed_nodes:
        node = view.node
        laser_scan = defaults.entry(node).message_types[0] if node.type == pb.LIDAR_PUBLISHER else ""
        if laser_scan and defaults.backend(node) == "CPP" and node.message_type not in ("", laser_scan):
            yield Finding(
                view.at("preferred_backend"),
                f"the C++ LIDAR_PUBLISHER publishes {laser_scan} only, not {node.message_type}; "
                "remove preferred_backend CPP to publish point clouds from the Python node",
            )
