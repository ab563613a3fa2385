"""ROS 2 domain ids for tests, each held by one test at a time on this machine.

A test claims its id, and the `SPARE_DOMAINS` ids after it (for a second robot, or a domain nobody
uses), with an exclusive lock on a file per id in `CLAIMS`. Tests running at once, in parallel workers
of one run or in runs of other checkouts, therefore never share a domain; the kernel drops a lock when
its holder dies, so a killed run leaves no claim behind. The search starts at a place derived from the
test's name, so a test mostly gets the same id from run to run.
"""

import contextlib
import fcntl
import os
import tempfile
import zlib
from collections.abc import Iterator
from pathlib import Path

FIRST_DOMAIN, LAST_DOMAIN = 1, 232  # every id ROS 2 allows, less 0: the default of a user's own ROS
SPARE_DOMAINS = 2  # ids after its own that a test may also use (ROS_DOMAIN_ID + 1, + 2)
CLAIMS = Path(tempfile.gettempdir()) / "joshua-test-ros-domains"


def _lock(domain: int) -> int | None:
    """An open descriptor holding the lock of `domain`, or None when another process holds it."""
    descriptor = os.open(CLAIMS / f"{domain}.lock", os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(descriptor)
        return None
    return descriptor


@contextlib.contextmanager
def claimed_domain(seed: str) -> Iterator[int]:
    """A domain id whose block (it and the spare ids after it) no other test holds, held until exit."""
    CLAIMS.mkdir(mode=0o777, exist_ok=True)
    bases = range(FIRST_DOMAIN, LAST_DOMAIN - SPARE_DOMAINS + 1)
    start = zlib.crc32(seed.encode()) % len(bases)
    for step in range(len(bases)):
        base = bases[(start + step) % len(bases)]
        held = []
        for domain in range(base, base + SPARE_DOMAINS + 1):
            descriptor = _lock(domain)
            if descriptor is None:
                break
            held.append(descriptor)
        try:
            if len(held) == SPARE_DOMAINS + 1:
                yield base
                return
        finally:
            for descriptor in held:
                os.close(descriptor)
    raise RuntimeError(f"every ROS domain id is held by other tests (claims in {CLAIMS})")
