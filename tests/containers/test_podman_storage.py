"""The tests' podman storage records a container's end: the cleanup command its exit runs accepts the storage's
run state directory, so a container that ended is `exited` (not left `stopped`, where every `podman run` and
`podman wait` waited out podman's 20 s before going on)."""

import time

import pytest
from robot_container import state

from testsupport.podman import PODMAN_TIMEOUT_S, unique_name

pytestmark = pytest.mark.timeout(PODMAN_TIMEOUT_S * 2)
RUNROOT_LIMIT = 50  # characters: podman's cleanup command refuses a longer --runroot


def test_a_container_that_ended_is_cleaned_up_by_its_exit_command(podman, base_image):
    assert len(str(podman.runroot)) <= RUNROOT_LIMIT, podman.runroot
    name = unique_name("ended")
    podman.run("run", "--detach", "--network=none", "--name", name, base_image, "true")
    try:
        deadline = time.monotonic() + PODMAN_TIMEOUT_S
        while (now := state(podman, name)) != "exited" and time.monotonic() < deadline:
            time.sleep(0.1)
        assert now == "exited", f"the container stayed {now!r}: its cleanup command did not run"
        assert podman.run("wait", name, timeout=PODMAN_TIMEOUT_S).stdout.strip() == "0"
    finally:
        podman.remove_container(name)
