"""What the ROS graph says about a topic: its types, endpoints with their QoS, and a QoS to subscribe with."""

from __future__ import annotations

import time

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from joshua_runtime.errors import JoshuaError

GRAPH_POLL_S = 0.05
SUBSCRIBE_DEPTH = 10


class TopicNotFound(JoshuaError):
    """No node in the domain publishes or subscribes to the topic."""


def wait_for_topic(node, executor, topic: str, timeout_s: float) -> list[str]:
    """The message types of `topic` once it appears in the graph; TopicNotFound after `timeout_s`."""
    deadline = time.monotonic() + timeout_s
    while True:
        types = dict(node.get_topic_names_and_types()).get(topic)
        if types:
            return types
        if time.monotonic() >= deadline:
            raise TopicNotFound(
                f"topic {topic} does not appear in ROS domain {node_domain(node)} within {timeout_s:g} s"
            )
        executor.spin_once(timeout_sec=GRAPH_POLL_S)


def discover(executor, seconds: float) -> None:
    """Let discovery announcements arrive for `seconds` (there is no daemon holding the graph)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=GRAPH_POLL_S)


def node_domain(node) -> int:
    return node.context.get_domain_id()


def subscription_qos(publishers) -> QoSProfile:
    """The QoS that hears every publisher: reliable and transient local only when all of them are."""
    profiles = [info.qos_profile for info in publishers]
    reliable = bool(profiles) and all(p.reliability == ReliabilityPolicy.RELIABLE for p in profiles)
    latched = bool(profiles) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
    return QoSProfile(
        depth=SUBSCRIBE_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def describe_endpoint(info) -> str:
    """Lines describing one publisher or subscription, as `ros2 topic info --verbose` does."""
    qos = info.qos_profile
    lines = [
        f"Node name: {info.node_name}",
        f"Node namespace: {info.node_namespace}",
        f"Topic type: {info.topic_type}",
        f"Endpoint type: {info.endpoint_type.name}",
        "QoS profile:",
        f"  Reliability: {qos.reliability.name}",
        f"  History (Depth): {qos.history.name} ({qos.depth})",
        f"  Durability: {qos.durability.name}",
        f"  Liveliness: {qos.liveliness.name}",
    ]
    return "\n".join(lines)
