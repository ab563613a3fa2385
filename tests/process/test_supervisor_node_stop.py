"""Stopping, restarting or losing one node ends everything it started, daemons and children that left its
process group included, before the node counts as stopped or starts again; so does the robot's stop.
With a cgroup per node and with /proc tracking (--no-cgroup)."""

import json
import os
import re
import signal
from pathlib import Path

import pytest
from supervisor_harness import (
    ESCAPE_MODES,
    Supervisor,
    alive,
    build,
    children_of,
    command_line,
    ctl,
    custom_node,
    escaped_launches,
    escaping_node,
    robot,
    wait_until,
)

CONTAINMENT = pytest.mark.parametrize("options", [(), ("--no-cgroup",)], ids=["cgroup", "tracking"])


def start(tmp_path: Path, nodes: list[str], *options: str) -> tuple[Path, Path, Supervisor]:
    out = build(tmp_path, robot([custom_node("steady", tmp_path / "events.log"), *nodes]))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, *options, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"))
    return out, sock, supervisor


def states(out: Path, sock: Path) -> dict:
    result = ctl(out, sock, "status", "--json")
    assert result.returncode == 0, result.stderr
    return {node["name"]: node for node in json.loads(result.stdout)["nodes"]}


@CONTAINMENT
@pytest.mark.parametrize("mode", ESCAPE_MODES)
def test_ctl_restart_and_stop_end_what_the_node_started_before_they_answer(tmp_path, options, mode):
    out, sock, supervisor = start(tmp_path, [escaping_node(tmp_path, mode)], *options)
    try:
        first = wait_until(lambda: escaped_launches(tmp_path, mode), "the node and its escaped child")[0]
        steady = states(out, sock)["steady"]["pid"]

        restarted = ctl(out, sock, "restart", mode)
        assert restarted.returncode == 0, restarted.stderr
        assert not any(alive(pid) for pid in first), f"the restart left {first} running\n{supervisor.log()}"
        second = wait_until(lambda: escaped_launches(tmp_path, mode)[1:], "the second launch")[0]
        assert all(alive(pid) for pid in second)

        assert ctl(out, sock, "stop", mode).stdout == f"{mode}: stopped\n"
        assert not any(alive(pid) for pid in second), f"the stop left {second} running\n{supervisor.log()}"
        now = states(out, sock)
        assert now[mode]["state"] == "stopped"
        assert (now["steady"]["state"], now["steady"]["pid"]) == ("running", steady)
        assert re.search(
            rf"^\[.*\] {mode}: SIGKILL also to 1 process it started outside its group", supervisor.log(), re.M
        )
    finally:
        supervisor.signal()
        supervisor.wait()


@CONTAINMENT
def test_a_node_that_dies_takes_what_it_started_along_before_its_restart(tmp_path, options):
    fields = "restart: RESTART_ON_FAILURE max_restarts: 1 critical: false"
    out, sock, supervisor = start(
        tmp_path, [escaping_node(tmp_path, "daemon", "3", name="dying", fields=fields)], *options
    )
    try:
        second = wait_until(lambda: escaped_launches(tmp_path, "dying")[1:], "the restart")[0]
        first = escaped_launches(tmp_path, "dying")[0]
        assert not any(alive(pid) for pid in first), f"{first} outlived the node's death\n{supervisor.log()}"
        supervisor.wait_log(r"dying: failed for good after 1 restarts")
        try:
            wait_until(lambda: not any(alive(pid) for pid in second), "what the last launch started to die")
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n{supervisor.log()}") from None
        assert states(out, sock)["dying"]["state"] == "failed"
        assert re.search(r"^\[.*\] dying: killing what it left behind", supervisor.log(), re.M)
    finally:
        supervisor.signal()
        supervisor.wait()


@CONTAINMENT
def test_the_robots_stop_ends_every_nodes_escaped_processes_itself_and_says_so(tmp_path, options):
    out, _, supervisor = start(tmp_path, [escaping_node(tmp_path, mode) for mode in ESCAPE_MODES], *options)
    try:
        wait_until(lambda: all(escaped_launches(tmp_path, mode) for mode in ESCAPE_MODES), "every escaped child")
        pids = [pid for mode in ESCAPE_MODES for pid in escaped_launches(tmp_path, mode)[0]]
        guard = next(pid for pid in children_of(supervisor.pid) if str(out / "supervisor.py") in command_line(pid))
        os.kill(guard, signal.SIGKILL)  # what is left after the supervisor's exit stays
        supervisor.wait_log(rf"guard process {guard} killed by SIGKILL")
        supervisor.signal()
        assert supervisor.wait() == 1  # the escaped processes ignore SIGINT and SIGTERM
        assert not any(alive(pid) for pid in pids), supervisor.log()
    finally:
        supervisor.close()
    log = supervisor.log()
    for mode in ESCAPE_MODES:
        for stage in ("SIGINT", "SIGTERM", "SIGKILL"):
            assert re.search(rf"^\[.*\] {mode}: {stage} also to 1 process it started outside its group", log, re.M), log
    assert "giving up" not in log
    cgroup = re.search(r"nodes run in cgroup (\S+)$", log, re.M)
    assert (cgroup is None) == bool(options)
    assert cgroup is None or not Path(cgroup.group(1)).exists()  # removed by the supervisor, the guard being gone
