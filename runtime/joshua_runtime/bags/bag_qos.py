"""A topic's QoS in a bag, as rosbag2 stores it: the `offered_qos_profiles` YAML of a channel and of metadata.yaml.

The text is a YAML list with one profile per publisher, each `{history, depth, reliability, durability,
deadline, lifespan, liveliness, liveliness_lease_duration, avoid_ros_namespace_conventions}`; the
policies are rmw's numbers (history 1 keep last, 2 keep all; reliability 1 reliable, 2 best effort;
durability 1 transient local, 2 volatile), as rosbag2 writes them in Humble. Jazzy's names
(`reliable`, `transient_local` ...) are read too. Durations of 0 mean rmw's default (none).
"""

import yaml
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

ZERO = {"sec": 0, "nsec": 0}
# What a bag without recorded QoS is played with (rosbag2's fallback as well: a reliable, volatile topic).
FALLBACK_DEPTH = 10


def to_yaml(profiles: list[QoSProfile]) -> str:
    """The `offered_qos_profiles` text of the publishers offering `profiles`."""
    return yaml.safe_dump([_entry(profile) for profile in profiles], sort_keys=False)


def _entry(profile: QoSProfile) -> dict:
    return {
        "history": int(profile.history),
        "depth": int(profile.depth),
        "reliability": int(profile.reliability),
        "durability": int(profile.durability),
        "deadline": dict(ZERO),
        "lifespan": dict(ZERO),
        "liveliness": 1,
        "liveliness_lease_duration": dict(ZERO),
        "avoid_ros_namespace_conventions": False,
    }


def _policy(enum, value):
    if isinstance(value, str):
        return enum[value.upper()]
    return enum(int(value))


def from_yaml(text: str) -> QoSProfile | None:
    """The profile to publish a recorded topic with, None when the bag has none (or an unreadable one).

    With several publishers: reliable only if every one was, transient local only if every one was,
    the deepest history of them (FALLBACK_DEPTH when none is known)."""
    try:
        entries = yaml.safe_load(text) if text else None
        if not entries or not isinstance(entries, list):
            return None
        reliability = [_policy(ReliabilityPolicy, e["reliability"]) for e in entries]
        durability = [_policy(DurabilityPolicy, e["durability"]) for e in entries]
        history = [_policy(HistoryPolicy, e["history"]) for e in entries]
        depth = max(int(e.get("depth", 0)) for e in entries)
    except (yaml.YAMLError, KeyError, ValueError, TypeError, AttributeError):
        return None
    keep_all = HistoryPolicy.KEEP_ALL in history
    return QoSProfile(
        history=HistoryPolicy.KEEP_ALL if keep_all else HistoryPolicy.KEEP_LAST,
        depth=0 if keep_all else depth or FALLBACK_DEPTH,  # 0: a history discovery could not tell
        reliability=ReliabilityPolicy.RELIABLE
        if all(r == ReliabilityPolicy.RELIABLE for r in reliability)
        else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL
        if all(d == DurabilityPolicy.TRANSIENT_LOCAL for d in durability)
        else DurabilityPolicy.VOLATILE,
    )


def fallback() -> QoSProfile:
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=FALLBACK_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )
