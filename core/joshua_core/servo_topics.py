"""Topics a node declares by its type alone: /diagnostics (servo nodes, the LEGO base), a servo command topic's preset channel."""

DIAGNOSTICS_TOPIC = "/diagnostics"
DIAGNOSTICS_TYPE = "diagnostic_msgs/msg/DiagnosticArray"
PRESET_SUFFIX = "/preset"
PRESET_TYPE = "std_msgs/msg/String"
# QoS of both, what diagnostic_updater, rqt and `ros2 topic pub` use: reliable, volatile, depth 10.
FIXED_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
DIAGNOSTICS_RATE_HZ = 1.0
# Preset commands every servo actuator understands besides its poses.
TORQUE_ON = "torque_on"
TORQUE_OFF = "torque_off"


def preset_topic(command_topic: str) -> str:
    """Where an actuator commanded on `command_topic` takes preset commands (std_msgs/String)."""
    return command_topic.rstrip("/") + PRESET_SUFFIX
