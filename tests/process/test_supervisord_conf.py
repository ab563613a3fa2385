"""The generated supervisord.conf under real supervisord and supervisorctl: start, status, stop, restarts."""

import json
import os
import re
import signal
import subprocess
import sys
import time
from datetime import datetime
from pathlib import Path

from supervisor_harness import WAIT_S, alive, build, custom_node, events, quoted, robot, wait_until

# Two starts of the crashing node with supervisord's back-off between them, its listener's stop of the
# robot and the other node's stop: seconds on a quiet machine, several times that on a loaded one.
FAILED_FOR_GOOD_S = 60.0

BIN = Path(sys.executable).parent
GROUP = "joshua-r"
CTL_POLL_S = 0.2  # supervisorctl is a whole Python process: ask less often than the harness polls files


class Supervisord:
    """supervisord running a generated supervisord.conf in the foreground."""

    def __init__(self, out: Path):
        self.conf = out / "supervisord.conf"
        self.log_path = out.parent / "supervisord.log"
        self.temporary = out.parent / "tmp"  # where supervisord keeps the logs the configuration leaves AUTO
        self.temporary.mkdir(exist_ok=True)
        with open(self.log_path, "w") as log:
            self.process = subprocess.Popen(
                [BIN / "supervisord", "-c", self.conf],
                stdout=log,
                stderr=subprocess.STDOUT,
                env={**os.environ, "TMPDIR": str(self.temporary)},
            )
        wait_until(lambda: (out / "supervisord.sock").exists(), "the control socket")

    def ctl(self, *args: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [BIN / "supervisorctl", "-c", self.conf, *args], capture_output=True, text=True, timeout=WAIT_S
        )

    def states(self) -> dict[str, str]:
        lines = self.ctl("status").stdout.splitlines()
        return {m.group(1): m.group(2) for m in (re.match(rf"{GROUP}:(\S+)\s+(\S+)", line) for line in lines) if m}

    def wait_states(self, wanted: dict[str, str]) -> dict[str, str]:
        return wait_until(
            lambda: (s := self.states()) and all(s.get(k) == v for k, v in wanted.items()) and s,
            f"supervisord states {wanted}",
            poll=CTL_POLL_S,
        )

    def log(self) -> str:
        return self.log_path.read_text()

    def log_times(self, pattern: str) -> list[float]:
        """Seconds since the epoch of supervisord's log lines matching `pattern`."""
        stamps = re.findall(r"^(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3}) \w+ " + pattern, self.log(), re.M)
        return [datetime.strptime(s, "%Y-%m-%d %H:%M:%S,%f").timestamp() for s in stamps]

    def close(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(WAIT_S)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()


def test_group_starts_reports_running_and_stops_every_node_at_once(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [custom_node("a", log), custom_node("b", log, "SIGINT=ignore"), custom_node("c", log, "SIGINT=ignore")],
            sigint=0.3,
            sigterm=0.3,
        ),
    )
    supervisord = Supervisord(out)
    try:
        supervisord.wait_states({"a": "RUNNING", "b": "RUNNING", "c": "RUNNING"})
        result = supervisord.ctl("stop", f"{GROUP}:*")
        assert result.returncode == 0, result.stdout + result.stderr
        assert supervisord.states() == {"a": "STOPPED", "b": "STOPPED", "c": "STOPPED"}
        received = {name: text for name, _, text in events(log) if text.startswith("got")}
        assert received == {"a": "got SIGINT exit", "b": "got SIGINT ignore", "c": "got SIGINT ignore"}
        assert not any(alive(pid) for _, pid, _ in events(log))
        stops = [supervisord.log_times(rf"waiting for {name} to stop")[0] for name in "bc"]
        kills = [supervisord.log_times(rf"killing '{name}' \(\d+\) with SIGKILL")[0] for name in "bc"]
        assert max(stops) - min(stops) < 0.5  # every node is told to stop at once...
        assert all(kill - min(stops) >= 0.9 for kill in kills)  # stopwaitsecs=1 (0.3 s + 0.3 s, rounded up)
        assert abs(kills[0] - kills[1]) < 0.5  # ...and killed in parallel, not one after the other
        result = supervisord.ctl("start", f"{GROUP}:*")
        assert result.returncode == 0, result.stdout + result.stderr
        assert supervisord.states() == {"a": "RUNNING", "b": "RUNNING", "c": "RUNNING"}
        assert len([e for e in events(log) if e[2] == "start"]) == 6
    finally:
        supervisord.close()


def test_restart_policies_map_to_autorestart_and_startretries(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot(
            [
                custom_node("crash", log, "exit_after=0", "code=3", max_restarts="2", critical="false"),
                custom_node("always", log, "exit_after=1.2", restart="RESTART_ALWAYS", critical="false"),
                custom_node("never", log, "exit_after=0", "code=0", restart="RESTART_NEVER"),
            ]
        ),
    )
    supervisord = Supervisord(out)
    try:
        states = supervisord.wait_states({"crash": "FATAL", "never": "EXITED"})
        assert states["always"] in ("RUNNING", "STARTING", "BACKOFF", "EXITED")  # EXITED: between a run and the next
        wait_until(
            lambda: len([e for e in events(log) if e[:1] == ("always",) and e[2] == "start"]) >= 2,
            "the always node to be restarted after exiting 0",
        )
    finally:
        supervisord.close()
    starts = [name for name, _, text in events(log) if text == "start"]
    assert starts.count("never") == 1
    # A start that outlived startsecs (a slow interpreter start on a busy machine) counts as started and
    # gives the next failures their retries afresh: the retries are counted after the last such start.
    crash_log = re.findall(r"(spawned: 'crash'|success: crash entered RUNNING)", supervisord.log())
    last_success = max((i for i, line in enumerate(crash_log) if line.startswith("success")), default=-1)
    assert crash_log[last_success + 1 :].count("spawned: 'crash'") == 3
    assert starts.count("crash") == crash_log.count("spawned: 'crash'")


def test_a_critical_node_failing_for_good_stops_supervisord_and_every_node(tmp_path):
    log = tmp_path / "events.log"
    out = build(
        tmp_path,
        robot([custom_node("crash", log, "exit_after=0", "code=3", max_restarts="1"), custom_node("steady", log)]),
    )
    supervisord = Supervisord(out)
    try:
        assert supervisord.process.wait(FAILED_FOR_GOOD_S) == 0
    finally:
        supervisord.close()
    assert [text for name, _, text in events(log) if name == "steady"] == ["start", "got SIGINT exit"]
    assert "crash: fatal: critical node failed for good; stopping the robot" in supervisord.log()
    assert list(supervisord.temporary.iterdir()) == []  # the listener's stdout is the event protocol, not a log


ODD = ["it's", 'say "hi"', "a ;b", "#c", "%(here)s", "$HOME", "new\n  line", "", "tab\tx", "é"]


def test_arguments_and_environment_reach_the_node_unchanged(tmp_path):
    log = tmp_path / "events.log"
    env_file = tmp_path / "env.json"
    values = ODD + ['"quoted"', "both ' and \""]
    env = " ".join(f"env {{ key: {quoted(f'V{i}')} value: {quoted(v)} }}" for i, v in enumerate(values))
    env += ' env { key: "DASH-KEY" value: "d" }'
    node = custom_node("odd", log, f"env_file={env_file}", *ODD)[:-1] + f" {env} }}"
    out = build(tmp_path, robot([node], extra="ros_domain_id: 3"))
    supervisord = Supervisord(out)
    try:
        wait_until(env_file.exists, "the node to write its environment")
        time.sleep(0.1)
        seen = json.loads(env_file.read_text())
    finally:
        supervisord.close()
    assert seen["argv"] == [f"env_file={env_file}", *ODD]
    assert {key: seen["env"][key] for key in (f"V{i}" for i in range(len(values)))} == {
        f"V{i}": v for i, v in enumerate(values)
    }
    assert seen["env"]["DASH-KEY"] == "d"
    assert seen["env"]["FASTRTPS_DEFAULT_PROFILES_FILE"] == str(
        out / "fastdds_profile_images.xml"
    )  # custom: may carry images
    assert (seen["env"]["PYTHONUNBUFFERED"], seen["env"]["ROS_DOMAIN_ID"]) == ("1", "3")
    assert seen["cwd"] == str(out)
