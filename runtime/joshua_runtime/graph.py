"""Message types of topics published outside the description, learnt from the ROS graph at start."""

import time

from joshua_core.settings import TopicSettings
from joshua_runtime.errors import DeviceError

TYPE_DISCOVERY_TIMEOUT_S = 15.0  # how long a node waits for an outside publisher to appear
TYPE_DISCOVERY_POLL_S = 0.1


def with_discovered_types(ros_node, topics, timeout_s: float = TYPE_DISCOVERY_TIMEOUT_S) -> list[TopicSettings]:
    """`topics` with every empty message_type filled in from the graph.

    joshuac writes "" when nothing in the description publishes a topic (warning W202): the
    publisher runs elsewhere, and its type is known once it appears. Raises DeviceError naming the
    topics whose publisher did not appear within `timeout_s`. A stop signal interrupts the wait.
    """
    unknown = [topic.name for topic in topics if not topic.message_type]
    deadline = time.monotonic() + timeout_s
    found: dict[str, str] = {}
    while unknown:
        for name, types in ros_node.get_topic_names_and_types():
            if name in unknown and types:
                found[name] = types[0]
        unknown = [name for name in unknown if name not in found]
        if not unknown:
            break
        if time.monotonic() >= deadline:
            raise DeviceError(
                f"no publisher of {', '.join(unknown)} appeared within {timeout_s:g} s, so its "
                "message type is unknown; start it, or declare its publisher in the description"
            )
        time.sleep(TYPE_DISCOVERY_POLL_S)
    filled = []
    for topic in topics:
        copy = TopicSettings()
        copy.CopyFrom(topic)
        copy.message_type = topic.message_type or found[topic.name]
        filled.append(copy)
    return filled
