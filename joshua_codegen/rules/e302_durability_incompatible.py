"""E302 durability-incompatible: a TRANSIENT_LOCAL subscription on a topic with a VOLATILE publisher.

What it checks:
    For every publisher and subscriber (topic_name) of a topic, the publisher's offered durability
    is at least the subscription's requested one (rclpy's qos_check_compatible verdict). Default:
    VOLATILE. The error is at the subscriber's qos_durability (or its topic_name when defaulted),
    with the publisher as a note.

Why it matters:
    DDS does not connect them: both sides get an "incompatible QoS" event and no data flows.

Example:
    node { type: ENCODER_PUBLISHER topic_name: "/arm" ... }             # VOLATILE by default
    node { type: ACTUATOR_SUBSCRIBER topic_name: "/arm" qos_durability: TRANSIENT_LOCAL ... }
    # error: publisher "encoder_publisher" offers VOLATILE, subscriber "actuator_subscriber" requires TRANSIENT_LOCAL
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.qos_conflicts import conflicts

CODE = "E302"
NAME = "durability-incompatible"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    return conflicts(ctx, "durability", "qos_durability")
