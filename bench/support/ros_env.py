"""The environment benchmark processes run in: a ROS domain of their own, discovery on this host only."""

import os
import zlib

DOMAIN_IDS = range(120, 220)  # a bench's own domain when the caller names none (tests give theirs)


def bench_environment(bench: str, **extra: str) -> dict[str, str]:
    """os.environ with ROS_DOMAIN_ID (kept when set, else derived from `bench` and this process),
    LOCALHOST discovery and unbuffered Python output, plus `extra`."""
    seed = zlib.crc32(f"{bench}:{os.getpid()}".encode())
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", PYTHONUNBUFFERED="1")
    env.setdefault("ROS_DOMAIN_ID", str(DOMAIN_IDS[seed % len(DOMAIN_IDS)]))
    env.update(extra)
    return env
