"""The supervisor's control socket through its `ctl` client: status, restart, stop, start, logs."""

import os
import stat
import subprocess
import sys

from control_harness import ctl, start_robot, status, talker_node
from supervisor_harness import custom_node, events, unstamped, wait_started, wait_until

from joshua_codegen.supervisor import node_log


def test_restart_stop_and_start_a_node_while_the_others_run(tmp_path):
    out, sock, _, log, supervisor = start_robot(tmp_path, talker_node())
    try:
        assert stat.S_IMODE(os.stat(sock).st_mode) == 0o600
        assert stat.S_IMODE(os.stat(sock.parent).st_mode) == 0o700
        before = status(out, sock)
        assert {name: node["state"] for name, node in before.items()} == {"steady": "running", "talker": "running"}
        assert before["steady"]["ready"] and before["steady"]["restarts"] == 0
        wait_started(log, "steady")  # a SIGINT before its handler is in place would end it unseen

        restarted = ctl(out, sock, "restart", "steady")
        new_pid = status(out, sock)["steady"]["pid"]
        assert restarted.returncode == 0 and restarted.stdout == f"steady: running (pid {new_pid})\n"
        assert new_pid != before["steady"]["pid"]
        wait_started(log, "steady", new_pid)
        assert [text for name, _, text in events(log) if name == "steady"] == ["start", "got SIGINT exit", "start"]
        assert status(out, sock)["talker"]["pid"] == before["talker"]["pid"]

        assert ctl(out, sock, "stop", "steady").stdout == "steady: stopped\n"
        stopped = status(out, sock)["steady"]
        assert (stopped["state"], stopped["pid"], stopped["restarts"], stopped["manual_restarts"]) == (
            "stopped",
            None,
            0,  # restarts counts those of the restart policy only
            1,
        )
        assert supervisor.process.poll() is None

        assert ctl(out, sock, "start", "steady").returncode == 0
        assert status(out, sock)["steady"]["state"] == "running"
    finally:
        supervisor.signal()
        code = supervisor.wait()
    assert code == 0
    assert not sock.exists()


def test_a_node_that_ignores_sigint_is_stopped_with_sigterm_after_the_grace(tmp_path):
    out, sock, _, log, supervisor = start_robot(
        tmp_path, custom_node("stubborn", tmp_path / "events.log", "SIGINT=ignore")
    )
    try:
        wait_started(log, "stubborn")  # it ignores SIGINT from then on
        assert ctl(out, sock, "stop", "stubborn").stdout == "stubborn: stopped\n"
        assert [text for name, _, text in events(log) if name == "stubborn"] == [
            "start",
            "got SIGINT ignore",
            "got SIGTERM exit",
        ]
        supervisor.wait_log(r"stubborn: still running: escalating to SIGTERM")
    finally:
        supervisor.signal()
        supervisor.wait()


def test_logs_shows_and_follows_a_nodes_output_kept_in_its_log_file(tmp_path):
    out, sock, logs, _, supervisor = start_robot(tmp_path, talker_node())
    try:
        wait_until(
            lambda: (
                "line 3" in (logs / "talker.log").read_text(errors="replace")
                if (logs / "talker.log").exists()
                else False
            ),
            "the talker's log file",
        )
        tail = ctl(out, sock, "logs", "talker", "-n", "2").stdout.splitlines()
        assert len(tail) == 2 and all(unstamped(line).startswith("line ") for line in tail)
        follower = subprocess.Popen(
            [
                sys.executable,
                str(out / "supervisor.py"),
                "ctl",
                "--control-socket",
                str(sock),
                "logs",
                "talker",
                "-n",
                "0",
                "-f",
            ],
            stdout=subprocess.PIPE,
            text=True,
        )
        try:
            first = int(unstamped(follower.stdout.readline()).split()[1])
            second = int(unstamped(follower.stdout.readline()).split()[1])
        finally:
            follower.terminate()
            follower.wait()
        assert second == first + 1
        assert "line 3" in supervisor.log()  # the output still reaches the supervisor's own output
    finally:
        supervisor.signal()
        supervisor.wait()


def test_bad_requests_answer_one_line_and_exit_1_and_without_a_supervisor_3(tmp_path):
    out, sock, _, _, supervisor = start_robot(tmp_path)
    try:
        unknown = ctl(out, sock, "restart", "nobody")
        assert (unknown.returncode, unknown.stderr) == (1, "supervisor.py ctl: error: no node named 'nobody'\n")
        again = ctl(out, sock, "start", "steady")
        assert again.returncode == 1 and "steady is already running" in again.stderr
    finally:
        supervisor.signal()
        supervisor.wait()
    gone = ctl(out, sock, "status")
    assert gone.returncode == 3 and gone.stderr.startswith(f"supervisor.py ctl: error: control socket {sock}: ")
    assert gone.stderr.count("\n") == 1


def test_a_log_file_is_rotated_at_its_cap_and_tail_reads_across_files(tmp_path, monkeypatch):
    monkeypatch.setattr(node_log, "LOG_MAX_BYTES", 100)
    log = node_log.NodeLog(str(tmp_path), "n")
    for number in range(40):
        log.append(f"line {number:02d}\n".encode())  # 8 bytes a line: 12 lines a file
    files = sorted(path.name for path in tmp_path.iterdir())
    assert files == ["n.log", "n.log.1", "n.log.2", "n.log.3"]
    assert all(path.stat().st_size <= 100 for path in tmp_path.iterdir())
    assert log.tail(20) == [f"line {number:02d}" for number in range(20, 40)]
