"""The dashboard's guards on their own: the Host allow-list."""

import socket

import pytest

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
