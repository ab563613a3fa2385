"""Helpers of the sensor tests: expected QoS, timeouts and an in-process rclpy client.

Node settings come from the compiler (testsupport/compiled_settings.py) and node
processes from testsupport/node_process.py.
"""

import time

from testsupport.node_process import NodeProcess

NODE_START_TIMEOUT_S = 30.0  # a cold rclpy process on a busy 2-core machine
MESSAGE_TIMEOUT_S = 15.0
DISCOVERY_POLL_S = 0.05
SHUTDOWN_CONTRACT_S = 0.5  # every node exits within this after SIGINT/SIGTERM (DESIGN.md)
# What the graph reports for an endpoint whose node announcement has not arrived yet.
UNKNOWN_NODE_NAME = "_NODE_NAME_UNKNOWN_"

# The QoS joshuac gives camera and lidar publishers, and every other node, when the description sets none.
SENSOR_QOS = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}
DEFAULT_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
SO100_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]


class RosClient:
    """An in-process rclpy node with helpers to inspect the graph and collect messages."""

    def __init__(self, context):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.node = rclpy.create_node("sensors_test_client", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)

    def spin_for(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)

    def publishers(self, topic: str, timeout: float = NODE_START_TIMEOUT_S, process: NodeProcess | None = None):
        """The publisher endpoints of `topic` once there is one."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            infos = self.node.get_publishers_info_by_topic(topic)
            if infos and all(info.node_name != UNKNOWN_NODE_NAME for info in infos):
                return infos
            if process is not None and process.process.poll() is not None:
                raise AssertionError(f"node exited with {process.process.returncode}: {process.wait()[1]}")
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        raise AssertionError(f"no publisher on {topic} within {timeout} s")

    def subscribers(self, topic: str, timeout: float = NODE_START_TIMEOUT_S):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            infos = self.node.get_subscriptions_info_by_topic(topic)
            if infos and all(info.node_name != UNKNOWN_NODE_NAME for info in infos):
                return infos
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        raise AssertionError(f"no subscription on {topic} within {timeout} s")

    def collect(self, message_class, topic: str, qos: dict, count: int, timeout: float = MESSAGE_TIMEOUT_S) -> list:
        """The first `count` messages received on `topic` with a subscription of `qos`."""
        from joshua_runtime.qos import qos_profile

        received = []
        subscription = self.node.create_subscription(message_class, topic, received.append, qos_profile(qos))
        try:
            deadline = time.monotonic() + timeout
            while len(received) < count and time.monotonic() < deadline:
                self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        finally:
            self.node.destroy_subscription(subscription)
        assert len(received) >= count, f"{len(received)} of {count} messages on {topic} within {timeout} s"
        return received[:count]
