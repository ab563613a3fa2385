"""Conversion of the QoS settings written by joshuac into rclpy QoSProfile objects."""

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from joshua_core.settings import QosSettings

_RELIABILITY = {"RELIABLE": ReliabilityPolicy.RELIABLE, "BEST_EFFORT": ReliabilityPolicy.BEST_EFFORT}
_DURABILITY = {"VOLATILE": DurabilityPolicy.VOLATILE, "TRANSIENT_LOCAL": DurabilityPolicy.TRANSIENT_LOCAL}
_HISTORY = {"KEEP_LAST": HistoryPolicy.KEEP_LAST, "KEEP_ALL": HistoryPolicy.KEEP_ALL}


def qos_profile(qos: QosSettings) -> QoSProfile:
    """Build a QoSProfile from the QoS of a topic of the settings."""
    history = _HISTORY[qos.history]
    depth = qos.depth if history == HistoryPolicy.KEEP_LAST else 0
    return QoSProfile(
        history=history,
        depth=depth,
        reliability=_RELIABILITY[qos.reliability],
        durability=_DURABILITY[qos.durability],
    )
