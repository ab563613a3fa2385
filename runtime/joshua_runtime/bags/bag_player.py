"""Publish a recorded bag with its original timing and QoS, so that every node sees it as live.

Each topic gets one publisher with the QoS its recording stored (bag_qos.py; without one, reliable
and volatile): a latched topic (transient local) keeps its last messages for subscribers that come
later, as its original publisher did. Message i is published `(t_i - t_first) / rate` after the
first, from `start_s` seconds into the bag; with `loop` the bag starts over after its last message.
Messages go out serialized, exactly as recorded (header stamps are not rewritten).

A reliable, volatile topic's publisher keeps at least the messages of its last REPAIR_WINDOW_S seconds
of play: a sample lost on the way to a subscriber on a busy machine is sent again when the subscriber
asks for it, at the writer's next heartbeat (every 3 s with Fast DDS's defaults); with the recorded
depth (10, say, at 40 messages a second) it would be gone by then. Subscribers see no difference:
history depth is not part of QoS matching.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from joshua_runtime.bags import bag_qos
from joshua_runtime.bags.bag_reader import Bag, BagTopic
from joshua_runtime.errors import SettingsError
from joshua_runtime.messages import message_class

NS_PER_S = 1_000_000_000
SLEEP_SLICE_S = 0.1  # longest single sleep, so that Ctrl-C is handled at once
REPAIR_WINDOW_S = 4.0  # how long a reliable, volatile topic's publisher can still send a message again
REPAIR_DEPTH_MAX = 200  # and at most this many messages of it (200 camera frames of 640x480: 184 MB)


@dataclass(frozen=True)
class PlayOptions:
    topics: list[str]  # empty: every topic of the bag
    rate: float = 1.0
    start_s: float = 0.0
    loop: bool = False


def chosen_topics(bag: Bag, wanted: list[str]) -> list[str]:
    """The topics to play: `wanted` (each must be in the bag) or all of the bag's."""
    unknown = [topic for topic in wanted if topic not in bag.topics]
    if unknown:
        raise SettingsError(
            f"{bag.path} has no topic {', '.join(unknown)} (it has {', '.join(sorted(bag.topics)) or 'none'})"
        )
    return list(wanted) or sorted(bag.topics)


def create_publishers(node, bag: Bag, topics: list[str], rate: float) -> dict:
    """One publisher per topic, with the recorded QoS (publish_qos); {topic: publisher}."""
    publishers = {}
    for topic in topics:
        recorded = bag.topics[topic]
        qos = publish_qos(recorded, bag.duration_s, rate)
        publishers[topic] = node.create_publisher(message_class(recorded.message_type), topic, qos)
    return publishers


def publish_qos(recorded: BagTopic, duration_s: float, rate: float) -> QoSProfile:
    """The recorded QoS; a reliable, volatile one keeps the messages of REPAIR_WINDOW_S seconds of play."""
    qos = bag_qos.from_yaml(recorded.offered_qos) or bag_qos.fallback()
    if (
        qos.reliability == ReliabilityPolicy.RELIABLE
        and qos.durability == DurabilityPolicy.VOLATILE
        and qos.history == HistoryPolicy.KEEP_LAST
    ):
        per_second = recorded.count / duration_s * rate if duration_s > 0 else recorded.count
        qos.depth = max(qos.depth, min(math.ceil(per_second * REPAIR_WINDOW_S), recorded.count, REPAIR_DEPTH_MAX))
    return qos


def wait_until(moment: float) -> None:
    while (left := moment - time.monotonic()) > 0:
        time.sleep(min(left, SLEEP_SLICE_S))


def play(bag: Bag, publishers: dict, options: PlayOptions) -> int:
    """Publish the bag (again and again with loop); the number of messages published."""
    start_ns = bag.start_ns + round(options.start_s * NS_PER_S)
    if options.start_s and start_ns > bag.end_ns:
        raise SettingsError(f"--start {options.start_s:g} is past the end of {bag.path} ({bag.duration_s:.3f} s long)")
    published = 0
    while True:
        began = time.monotonic()
        first_ns = None
        for topic, data, log_time in bag.messages(list(publishers), start_ns):
            first_ns = log_time if first_ns is None else first_ns
            wait_until(began + (log_time - first_ns) / NS_PER_S / options.rate)
            publishers[topic].publish(data)
            published += 1
        if not options.loop or first_ns is None:
            return published
