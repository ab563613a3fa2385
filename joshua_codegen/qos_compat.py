"""Whether a publisher's offered QoS satisfies a subscription's requested QoS (rclpy-free).

Same verdict as `rclpy.qos.qos_check_compatible` for the policies a description can set: a
subscription requests a minimum and a publisher offers a maximum, so RELIABLE subscriptions need
RELIABLE publishers and TRANSIENT_LOCAL subscriptions need TRANSIENT_LOCAL publishers. History and
depth never prevent a connection.
"""

from __future__ import annotations

# Policy -> its levels, weakest first; a publisher must offer at least the level requested.
LEVELS = {
    "reliability": ("BEST_EFFORT", "RELIABLE"),
    "durability": ("VOLATILE", "TRANSIENT_LOCAL"),
}


def incompatible_policies(offered: dict, requested: dict) -> list[str]:
    """The policies (`reliability`, `durability`) for which `offered` falls short of `requested`."""
    return [
        policy for policy, levels in LEVELS.items() if levels.index(offered[policy]) < levels.index(requested[policy])
    ]


def compatible(offered: dict, requested: dict) -> bool:
    return not incompatible_policies(offered, requested)
