"""What the ROS graph says about a topic: its types, endpoints with their QoS, and a QoS to subscribe with."""

from __future__ import annotations

import time

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from joshua_runtime.errors import JoshuaError

GRAPH_POLL_S = 0.05
SUBSCRIBE_DEPTH = 10


class TopicNotFound(JoshuaError):
    """No node in the domain publishes the topic (none subscribes to it either, or only subscribers do)."""


class NoMessage(JoshuaError):
    """The topic has publishers, but no message of theirs arrived in time."""


def deadline_after(timeout_s: float) -> float | None:
    """The monotonic time `timeout_s` from now; None (never) for 0, which means wait forever."""
    return time.monotonic() + timeout_s if timeout_s > 0 else None


def passed(deadline: float | None) -> bool:
    return deadline is not None and time.monotonic() >= deadline


def wait_for_topic(node, executor, topic: str, timeout_s: float) -> list[str]:
    """The message types of `topic` once it appears in the graph; TopicNotFound after `timeout_s` (0: never)."""
    deadline = deadline_after(timeout_s)
    while True:
        types = dict(node.get_topic_names_and_types()).get(topic)
        if types:
            return types
        if passed(deadline):
            raise TopicNotFound(
                f"topic {topic} does not appear in ROS domain {node_domain(node)} within {timeout_s:g} s"
            )
        executor.spin_once(timeout_sec=GRAPH_POLL_S)


def wait_for_publishers(node, executor, topic: str, timeout_s: float) -> tuple[list[str], list]:
    """(message types, publishers) of `topic` once at least one publisher of it is known.

    A topic can appear in the graph through a subscription before its publishers are discovered; a
    QoS chosen then would not match them (volatile: no latched message). TopicNotFound after
    `timeout_s` (0: wait forever).
    """
    deadline = deadline_after(timeout_s)
    while True:
        types = dict(node.get_topic_names_and_types()).get(topic)
        publishers = node.get_publishers_info_by_topic(topic) if types else []
        if publishers:
            return types, publishers
        if passed(deadline):
            if not types:
                raise TopicNotFound(
                    f"topic {topic} does not appear in ROS domain {node_domain(node)} within {timeout_s:g} s"
                )
            subscriptions = len(node.get_subscriptions_info_by_topic(topic))
            raise TopicNotFound(
                f"topic {topic} has no publisher in ROS domain {node_domain(node)} within {timeout_s:g} s "
                f"(only {subscriptions} subscription{'s' if subscriptions != 1 else ''})"
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
    """The QoS that hears every publisher, as `ros2 topic echo` chooses it: reliable only when all of them
    are, transient local (their kept messages delivered on joining) only when all of them are, and a
    history with room for what every publisher keeps (discovery may report a depth of 0: count 1)."""
    profiles = [info.qos_profile for info in publishers]
    reliable = bool(profiles) and all(p.reliability == ReliabilityPolicy.RELIABLE for p in profiles)
    latched = bool(profiles) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
    return QoSProfile(
        depth=max(SUBSCRIBE_DEPTH, sum(max(p.depth, 1) for p in profiles)),
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def describe_qos(qos: QoSProfile) -> str:
    """`RELIABLE, TRANSIENT_LOCAL, depth 10`: the policies that decide what a subscription hears."""
    return f"{qos.reliability.name}, {qos.durability.name}, depth {qos.depth}"


def describe_endpoint(info, verbose: bool = False) -> str:
    """Lines describing one publisher or subscription, as `ros2 topic info --verbose` does; `verbose` adds
    the endpoint's GID and its timing policies."""
    qos = info.qos_profile
    lines = [
        f"Node name: {info.node_name}",
        f"Node namespace: {info.node_namespace}",
        f"Topic type: {info.topic_type}",
        f"Endpoint type: {info.endpoint_type.name}",
    ]
    if verbose:
        lines.append(f"GID: {'.'.join(f'{byte:02x}' for byte in info.endpoint_gid)}")
    lines += [
        "QoS profile:",
        f"  Reliability: {qos.reliability.name}",
        f"  History (Depth): {qos.history.name} ({qos.depth})",
        f"  Durability: {qos.durability.name}",
        f"  Liveliness: {qos.liveliness.name}",
    ]
    if verbose:
        lines += [
            f"  Lifespan: {_duration(qos.lifespan)}",
            f"  Deadline: {_duration(qos.deadline)}",
            f"  Liveliness lease duration: {_duration(qos.liveliness_lease_duration)}",
        ]
    return "\n".join(lines)


def _duration(duration) -> str:
    nanoseconds = duration.nanoseconds
    return "Infinite" if nanoseconds in (0, 0x7FFFFFFFFFFFFFFF) else f"{nanoseconds} nanoseconds"
