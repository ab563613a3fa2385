"""A simulated computer that goes away (testsupport/hosts.py kills every process of its host) takes its robots'
cgroups along: the supervisor's guard, killed with it, cannot remove them, so the harness does."""

import glob
import os
import subprocess
import sys

from supervisor_harness import build, custom_node, events, robot, wait_until

from joshua_codegen.supervisor.containment import cgroup2_mount, own_cgroup
from testsupport.hosts import virtual_hosts


def robot_cgroups(pid: int) -> list[str]:
    return glob.glob(os.path.join(cgroup2_mount(), own_cgroup().lstrip("/"), f"joshua-r-{pid}"))


def test_closing_the_hosts_leaves_no_cgroup_of_the_robots_killed_with_them(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log), custom_node("b", log)]))
    with virtual_hosts("one") as network:
        supervisor = network["one"].popen(
            [sys.executable, "-S", str(out / "supervisor.py"), "--no-control"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        wait_until(lambda: len(events(log)) == 2, "both nodes to start")
        assert robot_cgroups(supervisor.pid), "the supervisor made no cgroup: nothing to test"
    assert robot_cgroups(supervisor.pid) == []
