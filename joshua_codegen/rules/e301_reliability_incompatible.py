"""E301 reliability-incompatible: a RELIABLE subscription on a topic with a BEST_EFFORT publisher.

What it checks:
    For every publisher and subscriber (topic_name) of a topic, the publisher's offered
    reliability is at least the subscription's requested one (rclpy's qos_check_compatible
    verdict). Defaults: BEST_EFFORT for camera and lidar publishers, RELIABLE otherwise. The error
    is at the subscriber's qos_reliability (or its topic_name when defaulted), with the publisher as
    a note.

Why it matters:
    DDS does not connect them: both sides get an "incompatible QoS" event and no data flows.

Example:
    node { type: CAMERA_PUBLISHER topic_name: "/camera" }               # BEST_EFFORT by default
    node { type: DATA_SUBSCRIBER topic_name: "/camera" qos_reliability: RELIABLE ... }
    # error: publisher "camera_publisher" offers BEST_EFFORT, subscriber "data_subscriber" requires RELIABLE
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.qos_conflicts import conflicts

CODE = "E301"
NAME = "reliability-incompatible"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    return conflicts(ctx, "reliability", "qos_reliability")
