"""The player's publishers: the recorded QoS, and a reliable, volatile topic's history deep enough to resend.

A reliable subscriber that lost a sample on the way asks for it at the publisher's next heartbeat; the
publisher can send it again only while its history still holds it. With the recorded depth (the arm's
10) at 40 messages a second that is a quarter of a second, so the player keeps REPAIR_WINDOW_S of play.
"""

import math

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from joshua_runtime.bags import bag_qos
from joshua_runtime.bags.bag_player import REPAIR_DEPTH_MAX, REPAIR_WINDOW_S, publish_qos
from joshua_runtime.bags.bag_reader import BagTopic


def recorded(count: int, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE, depth=10):
    profile = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth, reliability=reliability, durability=durability)
    return BagTopic("/arm", "sensor_msgs/msg/JointState", bag_qos.to_yaml([profile]), count)


def test_a_reliable_volatile_topic_keeps_the_messages_of_the_repair_window_at_the_played_rate():
    qos = publish_qos(recorded(count=1000), duration_s=50.0, rate=2.0)  # 20 a second, played at 40
    assert qos.depth == math.ceil(40 * REPAIR_WINDOW_S)
    assert (qos.reliability, qos.durability) == (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE)


def test_the_history_is_never_shallower_than_recorded_nor_deeper_than_the_bag_or_the_bound():
    assert publish_qos(recorded(count=1000, depth=500), 50.0, 1.0).depth == 500
    assert publish_qos(recorded(count=44), 2.0, 2.0).depth == 44
    assert publish_qos(recorded(count=100_000), 100.0, 1.0).depth == REPAIR_DEPTH_MAX
    assert publish_qos(recorded(count=1), 0.0, 1.0).depth == 10


def test_latched_and_best_effort_topics_keep_their_recorded_depth():
    # A latched topic's depth is how many messages a late subscriber gets; best effort never resends.
    assert publish_qos(recorded(1000, durability=DurabilityPolicy.TRANSIENT_LOCAL, depth=1), 50.0, 1.0).depth == 1
    assert publish_qos(recorded(1000, reliability=ReliabilityPolicy.BEST_EFFORT), 50.0, 1.0).depth == 10


def test_a_bag_without_qos_is_played_reliable_and_volatile_with_the_window():
    qos = publish_qos(BagTopic("/arm", "sensor_msgs/msg/JointState", "", 1000), 50.0, 1.0)
    assert (qos.reliability, qos.durability, qos.depth) == (
        ReliabilityPolicy.RELIABLE,
        DurabilityPolicy.VOLATILE,
        math.ceil(20 * REPAIR_WINDOW_S),
    )
