"""No descendant outlives a SIGKILLed supervisor: not a daemon that double-forked, not a child that called
setsid() or setpgid(); with a cgroup (where one can be made) and with /proc tracking (--no-cgroup)."""

import os
import re
import signal
import time
from pathlib import Path

import pytest
from supervisor_harness import (
    PYTHON,
    Supervisor,
    alive,
    build,
    quoted,
    robot,
    wait_until,
)

from joshua_codegen.supervisor.policy import TRACKING_POLL_S

# argv: PIDS_FILE MODE; MODE daemon (double fork, setsid), setsid or setpgid (one child that leaves
# the node's session or group). Every process writes "pid" lines to PIDS_FILE, then sleeps, deaf to
# SIGINT, SIGTERM and SIGHUP.
ESCAPE = r"""
import os, signal, sys, time
pids_file, mode = sys.argv[1], sys.argv[2]
for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(number, signal.SIG_IGN)

def note():
    with open(pids_file, "a") as out:
        out.write(f"{os.getpid()}\n")

note()
if os.fork() == 0:
    if mode == "daemon":
        os.setsid()
        if os.fork() != 0:
            os._exit(0)
    elif mode == "setsid":
        os.setsid()
    else:
        os.setpgid(0, 0)
    note()
while True:
    time.sleep(1)
"""

ESCAPING_PROCESSES = {"daemon": 2, "setsid": 2, "setpgid": 2}  # node + the one that left


def escaping_node(tmp_path: Path, mode: str) -> str:
    script = tmp_path / "escape.py"
    script.write_text(ESCAPE)
    args = ", ".join(quoted(a) for a in ["-I", "-S", str(script), str(tmp_path / f"{mode}.pids"), mode])
    return f'node {{ name: "{mode}" type: CUSTOM executable: "{PYTHON}" args: [{args}] }}'


def written_pids(tmp_path: Path) -> list[int]:
    return [
        int(line)
        for mode in ESCAPING_PROCESSES
        if (tmp_path / f"{mode}.pids").exists()
        for line in (tmp_path / f"{mode}.pids").read_text().split()
    ]


@pytest.mark.parametrize("options", [(), ("--no-cgroup",)], ids=["cgroup", "tracking"])
def test_sigkill_of_the_supervisor_leaves_no_daemon_or_escaped_child(tmp_path, options):
    out = build(tmp_path, robot([escaping_node(tmp_path, mode) for mode in ESCAPING_PROCESSES], sigint=30, sigterm=30))
    supervisor = Supervisor(out, *options)
    try:
        expected = sum(ESCAPING_PROCESSES.values())
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
