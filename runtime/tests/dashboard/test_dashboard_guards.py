"""The dashboard's guards on their own: the Host allow-list, the rate-limited log, the connection cap."""

import logging
import resource
import socket

import pytest

from joshua_runtime.dashboard.connections import (
    ACCEPT_BACKLOG,
    FD_RESERVE,
    MAX_CONNECTIONS,
    MIN_CONNECTIONS,
    connection_limit,
)
from joshua_runtime.dashboard.log_limit import BURST, REFILL_S, RateLimit
from joshua_runtime.dashboard.security import HostAllowList


@pytest.mark.parametrize(
    "bind, extra, allowed, refused",
    [
        ("127.0.0.1", (), ["127.0.0.1:8640", "localhost:8640", "LocalHost.:1", "localhost"], ["evil.test:8640", "127.0.0.2", "[::1]:8640", ""]),
        ("localhost", (), ["localhost:8640", "127.0.0.1:8640", "[::1]:8640"], ["robot:8640"]),
        ("::1", (), ["[::1]:8640", "localhost:8640"], ["127.0.0.1:8640"]),
        ("192.168.1.20", ("robot.example.org",), ["192.168.1.20:8640", "robot.example.org", "ROBOT.example.org:443"], ["192.168.1.21:8640", "example.org"]),
        ("0.0.0.0", (), ["10.1.2.3:8640", "[fe80::1]:8640", f"{socket.gethostname()}:8640", "localhost"], ["evil.test:8640", "10.1.2.3.evil.test"]),
    ],
)  # fmt: skip
def test_the_host_allow_list(bind, extra, allowed, refused):
    hosts = HostAllowList(bind, extra)
    for host in allowed:
        assert hosts.allows(host.encode()), host
    for host in refused:
        assert not hosts.allows(host.encode()), host
    assert not hosts.allows(None)


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def record(message: str, *args) -> logging.LogRecord:
    return logging.LogRecord("asyncio", logging.ERROR, __file__, 1, message, args, None)


def test_a_flood_of_one_error_becomes_a_burst_and_a_count():
    clock = Clock()
    limit = RateLimit(clock=clock)
    passed = [
        r
        for r in (record("socket.accept() out of system resource\nsocket: %d", n) for n in range(10_000))
        if limit.filter(r)
    ]
    assert len(passed) == BURST
    assert limit.filter(record("another kind of error"))  # each kind has its own bucket
    assert limit.pending() == [f"{10_000 - BURST} similar messages suppressed: socket.accept() out of system resource"]
    clock.now += REFILL_S
    after = record("socket.accept() out of system resource\nsocket: %d", 7)
    assert limit.filter(after)
    assert after.getMessage() == (
        f"socket.accept() out of system resource\nsocket: 7 [{10_000 - BURST} similar messages suppressed before this one]"
    )
    assert limit.pending() == []


def test_the_connection_cap_leaves_room_for_a_full_accept_queue_within_the_file_limit():
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    try:
        resource.setrlimit(resource.RLIMIT_NOFILE, (1024, hard))
        assert connection_limit() == MAX_CONNECTIONS
        resource.setrlimit(resource.RLIMIT_NOFILE, (FD_RESERVE + ACCEPT_BACKLOG + 100, hard))
        assert connection_limit() == 100
        resource.setrlimit(resource.RLIMIT_NOFILE, (64, hard))
        assert connection_limit() == MIN_CONNECTIONS
    finally:
        resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))
