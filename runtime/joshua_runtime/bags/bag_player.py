"""Publish a recorded bag with its original timing and QoS, so that every node sees it as live.

Each topic gets one publisher with the QoS its recording stored (bag_qos.py; without one, reliable
and volatile): a latched topic (transient local) keeps its last messages for subscribers that come
later, as its original publisher did. Message i is published `(t_i - t_first) / rate` after the
first, from `start_s` seconds into the bag; with `loop` the bag starts over after its last message.
Messages go out serialized, exactly as recorded (header stamps are not rewritten).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from joshua_runtime.bags import bag_qos
from joshua_runtime.bags.bag_reader import Bag
from joshua_runtime.errors import SettingsError
from joshua_runtime.messages import message_class

NS_PER_S = 1_000_000_000
SLEEP_SLICE_S = 0.1  # longest single sleep, so that Ctrl-C is handled at once


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


def create_publishers(node, bag: Bag, topics: list[str]) -> dict:
    """One publisher per topic, with the recorded QoS; {topic: publisher}."""
    publishers = {}
    for topic in topics:
        recorded = bag.topics[topic]
        qos = bag_qos.from_yaml(recorded.offered_qos) or bag_qos.fallback()
        publishers[topic] = node.create_publisher(message_class(recorded.message_type), topic, qos)
    return publishers


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
