"""A supervisor killed outright (SIGKILL) takes every node and every grandchild in their groups with it."""

import signal
from pathlib import Path

from supervisor_harness import Supervisor, alive, build, custom_node, events, robot, wait_until


def processes_running(script: Path) -> list[int]:
    """Live processes whose command line names `script` (the supervisor and its guard)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            command = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if str(script).encode() in command and alive(int(entry.name)):
            found.append(int(entry.name))
    return found


def test_sigkill_of_the_supervisor_leaves_no_child_or_grandchild(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [
                custom_node("cooperative", log),
                custom_node("deaf", log, "SIGINT=ignore", "SIGTERM=ignore"),
                custom_node("parent", log, "SIGINT=ignore", "SIGTERM=ignore", "grandchild=ignore"),
            ],
            sigint=30,
            sigterm=30,
        ),
    )
    supervisor = Supervisor(out)
    try:
        wait_until(lambda: len(events(log)) == 4, "three nodes and a grandchild to start")
        assert len(processes_running(out / "supervisor.py")) == 2  # the supervisor and its guard
        supervisor.signal(signal.SIGKILL)
        assert supervisor.wait() == -signal.SIGKILL
        pids = [pid for _, pid, _ in events(log)]
        wait_until(lambda: not any(alive(pid) for pid in pids), "every node and grandchild to die")
        wait_until(lambda: not processes_running(out / "supervisor.py"), "the guard to exit")
    finally:
        supervisor.close()
    assert {name for name, _, _ in events(log)} == {"cooperative", "deaf", "parent", "parent/grandchild"}
    assert all(text == "start" for _, _, text in events(log))  # killed outright: no signal was handled
