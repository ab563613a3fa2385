"""QoS profiles and timeouts of the simulation tests' rclpy client (ros_client and start_node: root conftest)."""

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

STARTUP_TIMEOUT_S = 30.0
DISCOVERY_TIMEOUT_S = 10.0

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
SENSOR = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
