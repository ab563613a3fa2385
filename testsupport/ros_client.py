"""An rclpy client inside the test process: listens to topics, publishes, and reads the ROS graph.

Shared by every test suite that watches node processes over ROS (importable as testsupport.ros_client;
the root conftest.py offers it as the `ros_client` fixture, in the test's ROS domain).
"""

import time
from collections import deque

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile

from joshua_core.settings import QosSettings
from joshua_runtime.qos import qos_profile

# Longest one spin waits for a callback before a wait checks its condition again.
SPIN_SLICE_S = 0.05
# What the graph names an endpoint's node until that node's announcement has arrived.
UNKNOWN_NODE_NAME = "_NODE_NAME_UNKNOWN_"


class _Inbox:
    """The last messages of one subscription (at most `keep` of them) and how many arrived in all."""

    def __init__(self, keep: int):
        self.messages: deque = deque(maxlen=keep)
        self.count = 0

    def receive(self, message) -> None:
        self.messages.append(message)
        self.count += 1


class RosClient:
    """A node in an rclpy context of its own, spun only while one of its waits runs.

    `qos` arguments are a QoSProfile or a QoS dict as in node settings
    (`{"history", "depth", "reliability", "durability"}`).
    """

    def __init__(self, name: str):
        self.name = name
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node(name, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._inboxes: dict[str, _Inbox] = {}
        self._subscriptions: dict[str, object] = {}

    def __enter__(self) -> "RosClient":
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def listen(self, topic: str, message_class, qos, keep: int = 1) -> None:
        """Subscribe to `topic`, keeping its last `keep` messages.

        Listening again to a topic replaces the earlier subscription and forgets what it received.
        """
        if topic in self._subscriptions:
            self.node.destroy_subscription(self._subscriptions.pop(topic))
        inbox = self._inboxes[topic] = _Inbox(keep)
        self._subscriptions[topic] = self.node.create_subscription(message_class, topic, inbox.receive, _profile(qos))

    def last(self, topic: str):
        """The last message received on `topic`, or None."""
        messages = self._inbox(topic).messages
        return messages[-1] if messages else None

    def messages(self, topic: str) -> list:
        """The kept messages of `topic`, oldest first."""
        return list(self._inbox(topic).messages)

    def count(self, topic: str) -> int:
        """How many messages arrived on `topic` since listening to it, kept or not."""
        return self._inbox(topic).count

    def publisher(self, topic: str, message_class, qos):
        return self.node.create_publisher(message_class, topic, _profile(qos))

    def spin_until(self, condition, timeout_s: float, every=None) -> bool:
        """Spin until `condition()` holds, calling `every()` before each spin; whether it held in time."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if every is not None:
                every()
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)
            if condition():
                return True
        return False

    def publishers_info(self, topic: str, timeout_s: float, every=None) -> list:
        """The publishers of `topic` of other nodes, once there is one and discovery names every one's node.

        What the graph shows at the timeout otherwise, so that a test's assertion shows it.
        """
        return self._endpoints_once_named(self.node.get_publishers_info_by_topic, topic, timeout_s, every)

    def subscriptions_info(self, topic: str, timeout_s: float, every=None) -> list:
        """The subscriptions to `topic` of other nodes, as publishers_info."""
        return self._endpoints_once_named(self.node.get_subscriptions_info_by_topic, topic, timeout_s, every)

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def _inbox(self, topic: str) -> _Inbox:
        if topic not in self._inboxes:
            raise KeyError(f"{self.name} does not listen to {topic}")
        return self._inboxes[topic]

    def _endpoints_once_named(self, query, topic: str, timeout_s: float, every) -> list:
        endpoints = []

        def all_named() -> bool:
            nonlocal endpoints
            endpoints = [info for info in query(topic) if info.node_name != self.name]
            return bool(endpoints) and all(info.node_name != UNKNOWN_NODE_NAME for info in endpoints)

        self.spin_until(all_named, timeout_s, every)
        return endpoints


def _profile(qos) -> QoSProfile:
    """A QoSProfile as it is, else QoS settings: a message or their literal form from compiled settings."""
    if isinstance(qos, QoSProfile):
        return qos
    return qos_profile(QosSettings(**qos) if isinstance(qos, dict) else qos)
