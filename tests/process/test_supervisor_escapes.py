"""No descendant outlives a SIGKILLed supervisor: not a daemon that double-forked, not a child that called
setsid() or setpgid(); with a cgroup (where one can be made) and with /proc tracking (--no-cgroup)."""

import os
import re
import signal
import time

import pytest
from supervisor_harness import (
    ESCAPE_MODES,
    Supervisor,
    alive,
    build,
    escaped_launches,
    escaping_node,
    robot,
    wait_until,
)

from joshua_codegen.supervisor.policy import TRACKING_POLL_S


def written_pids(tmp_path) -> list[int]:
    return [pid for mode in ESCAPE_MODES for launch in escaped_launches(tmp_path, mode) for pid in launch]


@pytest.mark.parametrize("options", [(), ("--no-cgroup",)], ids=["cgroup", "tracking"])
def test_sigkill_of_the_supervisor_leaves_no_daemon_or_escaped_child(tmp_path, options):
    out = build(tmp_path, robot([escaping_node(tmp_path, mode) for mode in ESCAPE_MODES], sigint=30, sigterm=30))
    supervisor = Supervisor(out, *options)
    try:
        expected = 2 * len(ESCAPE_MODES)  # each node and the process that left it
        wait_until(lambda: len(written_pids(tmp_path)) == expected, f"{expected} processes to start")
        time.sleep(3 * TRACKING_POLL_S)  # without a cgroup, the guard sees descendants at its next poll
        pids = written_pids(tmp_path)
        assert all(alive(pid) for pid in pids)
        supervisor.signal(signal.SIGKILL)
        assert supervisor.wait() == -signal.SIGKILL
        wait_until(lambda: not any(alive(pid) for pid in pids), "every descendant to die", timeout=5)
    finally:
        supervisor.close()
    cgroup = re.search(r"nodes run in cgroup (\S+)$", supervisor.log(), re.MULTILINE)
    if options:
        assert cgroup is None and "tracks their descendants through /proc" in supervisor.log()
    else:
        assert cgroup is not None, supervisor.log()
        wait_until(lambda: not os.path.exists(cgroup.group(1)), "the guard to remove the cgroup")
