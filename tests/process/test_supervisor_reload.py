"""`supervisor.py ctl reload OUT2` on real processes: what changed restarts, what is new starts, what is gone stops,
the rest keep their pids; a build of another robot, or one changed since it was built, is refused in one line."""

import hashlib
import json
import os
import time

import pytest
from control_harness import ctl, status
from supervisor_harness import Supervisor, build, command_line, custom_node, events, robot, wait_started, wait_until

SECOND_BUILT = 1767225600.25  # 2026-01-01T00:00:00.250Z: when the reloaded build's stamp was written
CONTAINMENT = pytest.mark.parametrize("options", [(), ("--no-cgroup",)], ids=["cgroup", "tracking"])


def stamp_hash(out) -> str:
    return hashlib.sha256((out / ".joshuac-stamp").read_bytes()).hexdigest()


def pids(out, sock) -> dict[str, int | None]:
    return {name: node["pid"] for name, node in status(out, sock).items()}


def start(tmp_path, config: str, *options: str):
    """Build `config` into tmp_path/v1/out and run it: (out, socket, Supervisor) once every node runs."""
    out = build(tmp_path / "v1", config)
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"), *options)
    supervisor.wait_log(r"supervisor: ready: \d+ of \d+ nodes ready")
    return out, sock, supervisor


def stop(supervisor) -> int:
    supervisor.signal()
    try:
        return supervisor.wait()
    finally:
        supervisor.close()


@CONTAINMENT
def test_a_changed_node_restarts_an_added_one_starts_a_removed_one_stops_and_the_rest_keep_their_pids(
    tmp_path, options
):
    log = tmp_path / "events.log"
    first = robot([custom_node("steady", log), custom_node("changed", log), custom_node("gone", log)])
    out, sock, supervisor = start(tmp_path, first, *options)
    try:
        before = pids(out, sock)
        for name, pid in before.items():  # a SIGINT before a program's handler is in place would end it unseen
            wait_started(log, name, pid)
        second = robot(
            [custom_node("steady", log), custom_node("changed", log, "exit_after=3600"), custom_node("added", log)],
            sigint=0.4,
        )
        out2 = build(tmp_path / "v2", second)
        os.utime(out2 / ".joshuac-stamp", (SECOND_BUILT, SECOND_BUILT))
        result = ctl(out, sock, "reload", str(out2))
        assert result.returncode == 0, result.stderr
        assert result.stdout.splitlines() == [
            f"reloaded robot r: build {stamp_hash(out)[:12]} -> {stamp_hash(out2)[:12]}",
            "restarted changed (command line)",
            "started added",
            "stopped gone",
            "unchanged: steady",
            "note: stops now wait 0.4 s after SIGINT and 0.3 s more after SIGTERM",
        ]
        after = status(out, sock)
        assert list(after) == ["steady", "changed", "added"]
        assert after["steady"]["pid"] == before["steady"]
        assert after["changed"]["pid"] not in (None, before["changed"])
        assert all(node["state"] == "running" for node in after.values())
        for name in ("changed", "added"):  # running once exec'd: their programs may not have written "start" yet
            wait_started(log, name, after[name]["pid"])
        by_node = {}
        for name, pid, text in events(log):
            by_node.setdefault(name, []).append((pid, text))
        assert by_node["steady"] == [(before["steady"], "start")]
        assert by_node["changed"] == [
            (before["changed"], "start"),
            (before["changed"], "got SIGINT exit"),
            (after["changed"]["pid"], "start"),
        ]
        assert by_node["gone"] == [(before["gone"], "start"), (before["gone"], "got SIGINT exit")]
        assert by_node["added"] == [(after["added"]["pid"], "start")]
        reply = json.loads(ctl(out, sock, "status", "--json").stdout)
        assert reply["run"]["build"] == stamp_hash(out2)
        # When the running build was written is the reloaded build's time now (the supervisor's local time).
        second_built = time.strftime("%Y-%m-%dT%H:%M:%S", time.localtime(SECOND_BUILT))
        assert reply["run"]["built"].startswith(second_built + ".250"), reply["run"]
        supervisor.wait_log(r"supervisor: ready: 3 of 3 nodes ready")
        assert "internal error" not in supervisor.log()
    finally:
        code = stop(supervisor)
    assert code == 0


def test_a_changed_setting_of_a_python_node_restarts_only_it_from_the_new_build(tmp_path, ros_env):
    def description(rate: int) -> str:
        return robot(
            [
                f'node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader" rate_hz: {rate} }}',
                'node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader" }',
            ],
            sigint=3,
            sigterm=1,
        )

    out = build(tmp_path / "v1", description(20))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"), env=ros_env)
    try:
        supervisor.wait_log(r"supervisor: ready: 2 of 2 nodes ready", timeout=60)
        before = pids(out, sock)
        out2 = build(tmp_path / "v2", description(25))
        result = ctl(out, sock, "reload", str(out2))
        assert result.returncode == 0, result.stderr
        assert "restarted leader (settings)" in result.stdout.splitlines()
        assert "unchanged: follower" in result.stdout.splitlines()
        after = pids(out, sock)
        assert after["follower"] == before["follower"] and after["leader"] not in (None, before["leader"])
        # The node runs from the new build: a node forked by the node starter names its entrypoint once it runs it.
        entrypoint = str(out2 / "nodes" / "leader.py")
        wait_until(lambda: entrypoint in command_line(after["leader"]), f"the leader's argv naming {entrypoint}", 30.0)
        supervisor.wait_log(r"ready: publishing /leader .*25 Hz", timeout=60)
    finally:
        code = stop(supervisor)
    assert code == 0


def test_a_build_of_another_robot_is_refused_in_one_line_and_nothing_changes(tmp_path):
    log = tmp_path / "events.log"
    out, sock, supervisor = start(tmp_path, robot([custom_node("steady", log)]))
    try:
        before = pids(out, sock)
        other = build(tmp_path / "v2", robot([custom_node("steady", log)]).replace('name: "r"', 'name: "other"', 1))
        result = ctl(out, sock, "reload", str(other))
        assert result.returncode == 1
        assert result.stdout == ""
        assert result.stderr == (
            f"supervisor.py ctl: error: cannot reload {other}: a build of robot 'other', not of robot 'r'\n"
        )
        assert pids(out, sock) == before
        assert json.loads(ctl(out, sock, "status", "--json").stdout)["run"]["build"] == stamp_hash(out)
    finally:
        code = stop(supervisor)
    assert code == 0


@pytest.mark.parametrize("changed", ["supervisor.py", "fastdds_profile_images.xml"])
def test_a_build_changed_since_it_was_built_is_refused(tmp_path, changed):
    log = tmp_path / "events.log"
    out, sock, supervisor = start(tmp_path, robot([custom_node("steady", log)]))
    try:
        before = pids(out, sock)
        out2 = build(tmp_path / "v2", robot([custom_node("steady", log), custom_node("added", log)]))
        with open(out2 / changed, "a") as edited:
            edited.write("\n")
        result = ctl(out, sock, "reload", str(out2))
        assert result.returncode == 1
        assert result.stderr == (
            f"supervisor.py ctl: error: cannot reload {out2}: {changed} differs from the build's .joshuac-stamp "
            "(changed after the build)\n"
        )
        assert pids(out, sock) == before
    finally:
        stop(supervisor)


def test_a_directory_that_is_no_build_is_refused(tmp_path):
    log = tmp_path / "events.log"
    out, sock, supervisor = start(tmp_path, robot([custom_node("steady", log)]))
    try:
        (tmp_path / "empty").mkdir()
        missing = ctl(out, sock, "reload", str(tmp_path / "nothing"))
        empty = ctl(out, sock, "reload", str(tmp_path / "empty"))
        assert (missing.returncode, empty.returncode) == (1, 1)
        assert missing.stderr == f"supervisor.py ctl: error: cannot reload {tmp_path / 'nothing'}: not a directory\n"
        assert empty.stderr == (
            f"supervisor.py ctl: error: cannot reload {tmp_path / 'empty'}: no supervisor.py in it: "
            "not a robot's build directory\n"
        )
    finally:
        stop(supervisor)


def test_a_node_the_new_build_cannot_start_refuses_the_reload(tmp_path):
    log = tmp_path / "events.log"
    out, sock, supervisor = start(tmp_path, robot([custom_node("steady", log)]))
    try:
        before = pids(out, sock)
        missing = 'node { name: "ghost" type: CUSTOM executable: "/nonexistent/ghost" }'
        out2 = build(tmp_path / "v2", robot([custom_node("steady", log), missing]))
        result = ctl(out, sock, "reload", str(out2))
        assert result.returncode == 1
        assert result.stderr == (
            f"supervisor.py ctl: error: cannot reload {out2}: ghost: program /nonexistent/ghost is not an "
            "executable file (or not on PATH)\n"
        )
        assert pids(out, sock) == before
        assert json.loads(ctl(out, sock, "status", "--json").stdout)["run"]["build"] == stamp_hash(out)
    finally:
        stop(supervisor)


def test_a_changed_file_the_node_reads_restarts_it_though_the_build_is_the_same(tmp_path):
    log = tmp_path / "events.log"
    program = tmp_path / "tool.sh"
    program.write_text(
        f"#!/bin/sh\necho tool $$ first >> {log}\ntrap 'exit 0' INT TERM\nwhile :; do sleep 0.05; done\n"
    )
    program.chmod(0o755)
    tool = f'node {{ name: "tool" type: CUSTOM executable: "{program}" }}'
    config = robot([custom_node("steady", log), tool])
    out, sock, supervisor = start(tmp_path, config)
    try:
        before = pids(out, sock)
        same = ctl(out, sock, "reload", str(build(tmp_path / "v2", config)))
        assert same.returncode == 0, same.stderr
        assert same.stdout.splitlines()[1:] == ["unchanged: steady, tool"]
        saved = tmp_path / "tool.sh.new"  # saved as editors do: a new file renamed over the old one
        saved.write_text(program.read_text().replace("first", "second"))
        saved.chmod(0o755)
        os.replace(saved, program)
        result = ctl(out, sock, "reload", str(build(tmp_path / "v3", config)))
        assert result.returncode == 0, result.stderr
        assert result.stdout.splitlines()[1:] == [f"restarted tool ({program} changed)", "unchanged: steady"]
        after = pids(out, sock)
        assert after["steady"] == before["steady"] and after["tool"] != before["tool"]
        wait_until(lambda: ("tool", after["tool"], "second") in events(log), "the new tool to start")
    finally:
        stop(supervisor)


def test_a_node_that_failed_for_good_starts_again_when_a_reload_changes_it(tmp_path):
    log = tmp_path / "events.log"
    broken = custom_node("flaky", log, "exit_after=0", "code=1", restart="RESTART_NEVER", critical="false")
    out = build(tmp_path / "v1", robot([custom_node("steady", log), broken]))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"))
    try:
        supervisor.wait_log(r"flaky: failed \(RESTART_NEVER\)")
        before = pids(out, sock)
        fixed = custom_node("flaky", log, restart="RESTART_NEVER", critical="false")
        result = ctl(out, sock, "reload", str(build(tmp_path / "v2", robot([custom_node("steady", log), fixed]))))
        assert result.returncode == 0, result.stderr
        assert "restarted flaky (command line)" in result.stdout.splitlines()
        after = status(out, sock)
        assert after["flaky"]["state"] == "running" and after["steady"]["pid"] == before["steady"]
    finally:
        stop(supervisor)


def test_a_build_whose_data_has_another_shape_is_refused_and_the_robot_runs_on(tmp_path):
    log = tmp_path / "events.log"
    out, sock, supervisor = start(tmp_path, robot([custom_node("steady", log)]))
    try:
        before = pids(out, sock)
        out2 = build(tmp_path / "v2", robot([custom_node("steady", log)]))
        script = out2 / "supervisor.py"
        text = script.read_text().replace("'env': {},", "'env': 5,", 1)
        script.write_text(text)  # restamped, so only its shape is wrong
        stamp = out2 / ".joshuac-stamp"
        digest = hashlib.sha256(text.encode()).hexdigest()
        lines = [
            f"{digest}  supervisor.py" if line.endswith("  supervisor.py") else line
            for line in stamp.read_text().splitlines()
        ]
        stamp.write_text("\n".join(lines) + "\n")
        result = ctl(out, sock, "reload", str(out2))
        assert result.returncode == 1
        assert result.stderr == (
            f"supervisor.py ctl: error: cannot reload {out2}: its data is not of this supervisor's format (TypeError)\n"
        )
        assert pids(out, sock) == before
        assert "internal error" not in supervisor.log()
    finally:
        code = stop(supervisor)
    assert code == 0
