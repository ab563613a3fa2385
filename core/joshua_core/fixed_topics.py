"""Topics a node type publishes by its type alone, whatever its fields say: transforms and the robot model."""

from dataclasses import dataclass

TF_MESSAGE = "tf2_msgs/msg/TFMessage"


@dataclass(frozen=True)
class FixedTopic:
    """One topic a node type always publishes, with the QoS its runtime publishes it with."""

    name: str  # fully qualified
    message_type: str
    depth: int
    reliability: str  # RELIABLE or BEST_EFFORT
    durability: str  # VOLATILE or TRANSIENT_LOCAL (kept for subscribers that join later)

    @property
    def qos(self) -> dict:
        """The QoS as the fields of joshua_core.settings.QosSettings (and of the manifest)."""
        return {
            "history": "KEEP_LAST",
            "depth": self.depth,
            "reliability": self.reliability,
            "durability": self.durability,
        }


# Moving frames, as tf2's TransformBroadcaster publishes them.
TF = FixedTopic("/tf", TF_MESSAGE, 100, "RELIABLE", "VOLATILE")
# Frames that never move, sent once and kept for late subscribers (tf2's StaticTransformBroadcaster).
TF_STATIC = FixedTopic("/tf_static", TF_MESSAGE, 1, "RELIABLE", "TRANSIENT_LOCAL")
# The URDF text, sent once and kept for late subscribers (as ros2's robot_state_publisher does).
ROBOT_DESCRIPTION = FixedTopic("/robot_description", "std_msgs/msg/String", 1, "RELIABLE", "TRANSIENT_LOCAL")
