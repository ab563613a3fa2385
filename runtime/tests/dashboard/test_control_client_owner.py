"""The dashboard's control client talks only to a supervisor of its own user or root: a socket another user
bound at the path first gets no request."""

import asyncio
import os

import pytest

from joshua_runtime.dashboard.control_client import ControlClient, ControlError
from testsupport.other_user import OTHER_UID, as_other_user

pytestmark = pytest.mark.process


def test_a_socket_another_user_serves_gets_no_request(tmp_path):
    shared = tmp_path / "tmp"
    shared.mkdir()
    shared.chmod(0o1777)
    sock = shared / f"joshua-{os.getuid()}" / "robot.sock"
    other = as_other_user(shared, "prebind", str(sock.relative_to(shared)))
    try:
        assert other.stdout.readline() == "ready\n"
        with pytest.raises(ControlError) as refused:
            asyncio.run(ControlClient(sock).status())
        assert str(refused.value) == (
            f"control socket {sock} is served by uid {OTHER_UID}, not by uid {os.geteuid()} or root"
        )
    finally:
        other.kill()
        heard = other.communicate()[0]
    assert "status" not in heard
