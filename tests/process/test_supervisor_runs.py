"""Each start of the supervisor is a run, marked with its id, start time and build in the supervisor's output and in
every node's log file: `ctl logs` shows the current run, `--all` the earlier ones too, every line time-stamped."""

import hashlib
import json
import os
import re

from control_harness import ctl, talker_node
from supervisor_harness import Supervisor, build, custom_node, robot, wait_until

# ISO 8601 with milliseconds and the offset of TZ=JST-9 (9 hours east of UTC), the time zone these runs use.
STAMP = r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}\+09:00"
HEADER = (
    r"-- run (?P<id>[0-9a-f]{8}): robot r, build (?P<build>[0-9a-f]{12}), supervisor pid \d+, started " + STAMP + " --"
)
BROKEN = "import sys\nprint('arm starting', flush=True)\nimport joshua_no_such_module\n"
HEALTHY = "import time\nprint('arm healthy', flush=True)\ntime.sleep(3600)\n"


def run_broken_arm(tmp_path) -> str:
    """Build a robot whose node `arm` fails with an ImportError, run it until `arm` failed, stop it: the run's id."""
    arm = talker_node("arm", BROKEN, extra="restart: RESTART_NEVER critical: false")
    out = build(tmp_path, robot([custom_node("steady", tmp_path / "events.log"), arm]))
    env = dict(os.environ, TZ="JST-9")
    sock, logs = tmp_path / "run" / "r.sock", tmp_path / "logs"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(logs), env=env)
    try:
        header = supervisor.wait_log(r"^\[\s*[\d.]+\] supervisor: " + HEADER + "$")
        supervisor.wait_log(r"arm: failed \(RESTART_NEVER\); not critical")
        supervisor.signal()
        assert supervisor.wait() == 5  # a node failed for good
    finally:
        supervisor.close()
    stamp = hashlib.sha256((out / ".joshuac-stamp").read_bytes()).hexdigest()
    assert header["build"] == stamp[:12]  # what `sha256sum OUT/.joshuac-stamp` prints
    return header["id"]


def test_ctl_logs_shows_the_current_run_and_all_shows_every_run_each_under_its_header(tmp_path):
    first = run_broken_arm(tmp_path)
    out = build(tmp_path, robot([custom_node("steady", tmp_path / "events.log"), talker_node("arm", HEALTHY)]))
    env = dict(os.environ, TZ="JST-9")
    sock, logs = tmp_path / "run" / "r.sock", tmp_path / "logs"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(logs), env=env)
    try:
        second = supervisor.wait_log(r"supervisor: " + HEADER)["id"]
        assert second != first
        wait_until(lambda: "arm healthy" in (logs / "arm.log").read_text(errors="replace"), "arm's output")
        current = ctl(out, sock, "logs", "arm")
        assert current.returncode == 0, current.stderr
        lines = current.stdout.splitlines()
        assert re.fullmatch(STAMP + " " + HEADER, lines[0]) and f"-- run {second}:" in lines[0]
        assert [line.split(" ", 1)[1] for line in lines[1:]] == ["arm healthy"]
        assert all(re.match(STAMP + " ", line) for line in lines)

        history = ctl(out, sock, "logs", "arm", "--all").stdout.splitlines()
        texts = [line.split(" ", 1)[1] for line in history]
        assert all(re.match(STAMP + " ", line) for line in history)
        runs = [index for index, text in enumerate(texts) if re.fullmatch(HEADER, text)]
        assert len(runs) == 2 and f"-- run {first}:" in texts[runs[0]] and f"-- run {second}:" in texts[runs[1]]
        assert "ModuleNotFoundError: No module named 'joshua_no_such_module'" in texts[runs[0] : runs[1]]
        assert texts[runs[1] + 1 :] == ["arm healthy"]

        steady = ctl(out, sock, "logs", "steady").stdout.splitlines()  # a node that prints nothing: its header
        assert len(steady) == 1 and f"-- run {second}:" in steady[0]

        shown = json.loads(ctl(out, sock, "status", "--json").stdout)["run"]
        stamp = hashlib.sha256((out / ".joshuac-stamp").read_bytes()).hexdigest()
        assert shown["id"] == second and shown["build"] == stamp
        assert re.fullmatch(STAMP, shown["started"])
    finally:
        supervisor.signal()
        supervisor.wait()


def test_status_tells_when_the_build_was_written_from_its_stamp(tmp_path):
    out = build(tmp_path, robot([custom_node("steady", tmp_path / "events.log")]))
    os.utime(out / ".joshuac-stamp", (1767225600.25, 1767225600.25))  # 2026-01-01T00:00:00.250Z, as a copy keeps it
    env = dict(os.environ, TZ="JST-9")
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"), env=env)
    try:
        supervisor.wait_log(r"supervisor: " + HEADER)
        shown = json.loads(ctl(out, sock, "status", "--json").stdout)["run"]
        assert shown["built"] == "2026-01-01T09:00:00.250+09:00"
    finally:
        supervisor.signal()
        supervisor.wait()
