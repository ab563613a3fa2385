"""Who made a set of simulated hosts, and removing the sets whose maker died without cleaning up.

A set is named `jth<pid>x<n>` after the process that made it; its directory STATE_ROOT/<set>/ holds
OWNER_FILE with that pid and the process's start time (so a reused pid is not taken for the maker),
and its network namespaces are named `<set>-<part>`. A set whose maker is gone (killed by a test
runner's timeout, say) is removed by the next set made on the machine: the processes left in its
namespaces (all started by that maker) are killed, the namespaces deleted, its directory unmounted.
"""

import glob
import json
import os
import re
import signal
import time
from pathlib import Path

from joshua_codegen.supervisor import containment
from testsupport import host_namespaces as ns

SET_PREFIX = "jth"
OWNER_FILE = "owner.json"
SET_NAME = re.compile(rf"^{SET_PREFIX}(\d+)x\d+$")
NAMESPACE_NAME = re.compile(rf"^({SET_PREFIX}(\d+)x\d+)-")
KILL_WAIT_S = 5.0  # how long a killed process may take to leave its namespace
KILL_POLL_S = 0.05


def process_start_ticks(pid: int) -> int | None:
    """The start time of process `pid` in clock ticks since boot (field 22 of /proc/PID/stat), None if gone."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return int(stat.rsplit(")", 1)[1].split()[19])


def write_owner(state_dir: Path) -> None:
    pid = os.getpid()
    (state_dir / OWNER_FILE).write_text(json.dumps({"pid": pid, "start_ticks": process_start_ticks(pid)}))


def owner_alive(set_name: str, state_dir: Path) -> bool:
    """Whether the process that made the set still runs (by pid and start time when recorded)."""
    try:
        owner = json.loads((state_dir / OWNER_FILE).read_text())
    except (OSError, ValueError):
        match = SET_NAME.match(set_name)
        return match is not None and process_start_ticks(int(match.group(1))) is not None
    return process_start_ticks(owner["pid"]) == owner["start_ticks"]


def kill_namespace_processes(namespace: str) -> None:
    """SIGKILL every process in the network namespace and wait (bounded) until none is left; then remove the
    cgroups the robots' supervisors among them made, which their guards, killed as well, did not."""
    deadline = time.monotonic() + KILL_WAIT_S
    killed = set()
    while pids := ns.network_namespace_pids(namespace):
        for pid in pids:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        killed.update(pids)
        if time.monotonic() > deadline:
            raise ns.HostSetupError(f"processes {pids} in namespace {namespace} did not end after SIGKILL")
        time.sleep(KILL_POLL_S)
    remove_supervisor_cgroups(killed)


def remove_supervisor_cgroups(supervisors: set[int]) -> None:
    """Remove the cgroups `joshua-<robot>-<pid>` that supervisors of these pids made below this process's cgroup
    (the hosts' processes share it: a network namespace has the machine's cgroups)."""
    mount, own = containment.cgroup2_mount(), containment.own_cgroup()
    if mount is None or own is None:
        return
    for pid in supervisors:
        for path in glob.glob(os.path.join(mount, own.lstrip("/"), f"joshua-*-{pid}")):
            containment.remove_cgroup(path)


def remove_set(set_name: str) -> None:
    """Kill what runs in the set's namespaces, delete them, then unmount and remove its directory."""
    for namespace in ns.network_namespaces():
        match = NAMESPACE_NAME.match(namespace)
        if match and match.group(1) == set_name:
            kill_namespace_processes(namespace)
            ns.delete_network_namespace(namespace)
    ns.remove_state_dir(ns.STATE_ROOT / set_name)


def remove_stale_sets() -> list[str]:
    """Remove every set whose maker is dead; return their names."""
    stale = set()
    if ns.STATE_ROOT.is_dir():
        for state_dir in ns.STATE_ROOT.iterdir():
            if SET_NAME.match(state_dir.name) and not owner_alive(state_dir.name, state_dir):
                stale.add(state_dir.name)
    for namespace in ns.network_namespaces():
        match = NAMESPACE_NAME.match(namespace)
        if match and not (ns.STATE_ROOT / match.group(1)).exists():
            if process_start_ticks(int(match.group(2))) is None:
                stale.add(match.group(1))
    for set_name in sorted(stale):
        remove_set(set_name)
    return sorted(stale)
