"""Build small robots into tmp_path and drive their generated supervisor on real processes."""

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

from google.protobuf import text_format

from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.write import write_tree
from joshua_core.schema import RobotDescription
from testsupport.description_text import quoted

PYTHON = sys.executable
WAIT_S = 10.0  # the longest any single wait of these tests may take before it fails
POLL_S = 0.01

# A node program: records what happens to it in a log file, reacts to signals as told.
# argv: LOG NAME [SIGINT=exit|ignore] [SIGTERM=exit|ignore] [exit_after=S] [code=N]
#       [grandchild=same|ignore|escape] [env_file=PATH (environment, arguments and directory as JSON)]
BEHAVE = r"""
import json, os, signal, sys, time
log_path, name = sys.argv[1], sys.argv[2]
options = dict(arg.split("=", 1) for arg in sys.argv[3:] if "=" in arg)

def note(text):
    with open(log_path, "a") as log:
        log.write(f"{name} {os.getpid()} {text}\n")

def on_signal(number, frame):
    signame = signal.Signals(number).name
    action = options.get(signame, "exit")
    note(f"got {signame} {action}")
    if action == "exit":
        os._exit(0)

for number in (signal.SIGINT, signal.SIGTERM):
    signal.signal(number, on_signal)
if "env_file" in options:
    with open(options["env_file"], "w") as out:
        json.dump({"env": dict(os.environ), "argv": sys.argv[3:], "cwd": os.getcwd()}, out)
kind = options.get("grandchild")
if kind and os.fork() == 0:
    if kind == "escape":
        os.setsid()
    if kind in ("ignore", "escape"):
        for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(number, signal.SIG_IGN)
    name = name + "/grandchild"
    note("start")
    while True:
        time.sleep(1)
note("start")
if "exit_after" in options:
    time.sleep(float(options["exit_after"]))
    note("exit")
    os._exit(int(options.get("code", "0")))
while True:
    time.sleep(1)
"""

# A node program whose child escapes its process group: argv PIDS_FILE MODE [EXIT_CODE], MODE daemon
# (double fork, setsid), setsid or setpgid (one child that leaves the node's session or group). The node
# writes its pid to PIDS_FILE, then the escaped process writes its own; once it has, the node exits with
# EXIT_CODE when given, else sleeps. Every process is deaf to SIGINT, SIGTERM and SIGHUP.
ESCAPE = r"""
import os, signal, sys, time
pids_file, mode = sys.argv[1], sys.argv[2]
for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(number, signal.SIG_IGN)

def note():
    with open(pids_file, "a") as out:
        out.write(f"{os.getpid()}\n")

note()
read_end, write_end = os.pipe()
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
    os.write(write_end, b"x")
    while True:
        time.sleep(1)
os.read(read_end, 1)
if len(sys.argv) > 3:
    os._exit(int(sys.argv[3]))
while True:
    time.sleep(1)
"""
ESCAPE_MODES = ("daemon", "setsid", "setpgid")


def escaping_node(directory: Path, mode: str, *args: str, name: str | None = None, fields: str = "") -> str:
    """A CUSTOM node named `name` (default: `mode`) running ESCAPE; its pids go to DIRECTORY/NAME.pids."""
    script = directory / "escape.py"
    script.write_text(ESCAPE)
    name = name or mode
    argv = ", ".join(quoted(a) for a in ["-I", "-S", str(script), str(directory / f"{name}.pids"), mode, *args])
    return f'node {{ name: "{name}" type: CUSTOM executable: "{PYTHON}" args: [{argv}] {fields} }}'


def escaped_launches(directory: Path, name: str) -> list[tuple[int, int]]:
    """(node pid, escaped pid) of every launch of the ESCAPE node `name` whose escaped process has started."""
    path = directory / f"{name}.pids"
    pids = [int(line) for line in path.read_text().split()] if path.exists() else []
    return list(zip(pids[0::2], pids[1::2]))


CPP_STAND_IN = r"""#!/bin/sh
printf '%s\n' "$0" "$@" > "$(dirname "$0")/argv.txt"
trap 'exit 0' INT TERM
while :; do sleep 0.05; done
"""


def describe(text: str) -> RobotDescription:
    return text_format.Parse(text, RobotDescription())


def build(directory: Path, config: str, source: str = "robot.pbtxt", prefix: str | None = None) -> Path:
    """Plan, render and write a description; the output directory."""
    out = directory / "out"
    write_tree(render(plan(describe(config), source), prefix), out)
    return out


def custom_node(name: str, log: Path, *options: str, **fields: str) -> str:
    """A CUSTOM node running the BEHAVE program with `options`."""
    script = log.parent / "behave.py"
    if not script.exists():
        script.write_text(BEHAVE)
    args = ", ".join(quoted(a) for a in ["-I", "-S", str(script), str(log), name, *options])
    extra = " ".join(f"{key}: {value}" for key, value in fields.items())
    return f'node {{ name: "{name}" type: CUSTOM executable: "{PYTHON}" args: [{args}] {extra} }}'


def robot(nodes: list[str], sigint: float = 0.3, sigterm: float = 0.3, extra: str = "") -> str:
    body = "\n".join(nodes)
    return (
        f'robot_config {{ name: "r" mode: MODE_TELEOPERATION '
        f"shutdown {{ sigint_grace_s: {sigint} sigterm_grace_s: {sigterm} }} {extra}\n{body}\n}}"
    )


def events(log: Path) -> list[tuple[str, int, str]]:
    """(node name, pid, text) of every line the BEHAVE programs wrote."""
    if not log.exists():
        return []
    lines = []
    for line in log.read_text().splitlines():
        name, pid, text = line.split(" ", 2)
        lines.append((name, int(pid), text))
    return lines


def wait_until(predicate, what: str, timeout: float = WAIT_S, poll: float = POLL_S):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(poll)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def wait_started(log: Path, name: str, pid: int | None = None) -> None:
    """Wait until the BEHAVE program of node `name` (of process `pid` when given) wrote "start": its signal
    handlers are in place. The supervisor counts a CUSTOM node started, and ready, once it is exec'd; a signal
    before this ends it as the signal does."""
    wait_until(
        lambda: any(e[0] == name and e[2] == "start" and pid in (None, e[1]) for e in events(log)),
        f"{name} to start" if pid is None else f"{name} (pid {pid}) to start",
    )


def process_state(pid: int) -> str | None:
    """The /proc state letter of a process (Z for a zombie), or None when it is gone."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return stat.rsplit(")", 1)[1].split()[0]


def parent_of(pid: int) -> int | None:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return int(stat.rsplit(")", 1)[1].split()[1])


def zombies_of(parent: int) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and parent_of(int(entry.name)) == parent and process_state(int(entry.name)) == "Z":
            found.append(int(entry.name))
    return found


def children_of(pid: int) -> list[int]:
    try:
        return [int(child) for child in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def command_line(pid: int) -> list[str]:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace").split("\0")
    except OSError:
        return []


def alive(pid: int) -> bool:
    return process_state(pid) not in (None, "Z")


class Supervisor:
    """A running generated supervisor whose log goes to a file."""

    def __init__(self, out: Path, *args: str, cwd: Path | None = None, env: dict | None = None):
        self.log_path = out.parent / "supervisor.log"
        self.log_file = open(self.log_path, "w")
        self.started = time.monotonic()
        self.process = subprocess.Popen(
            [PYTHON, str(out / "supervisor.py"), *args],
            stdout=self.log_file,
            stderr=subprocess.STDOUT,
            cwd=cwd or out.parent,
            env=env,
        )
        self.pid = self.process.pid

    def log(self) -> str:
        return self.log_path.read_text()

    def wait_log(self, pattern: str, timeout: float = WAIT_S) -> re.Match:
        """The first match of `pattern` in the supervisor's log; a timeout's message holds the log as it was."""
        try:
            return wait_until(
                lambda: re.search(pattern, self.log(), re.M), f"{pattern!r} in the supervisor log", timeout
            )
        except AssertionError as exc:
            raise AssertionError(f"{exc}; the log:\n{self.log()}") from None

    def signal(self, number: int = signal.SIGINT) -> float:
        self.process.send_signal(number)
        return time.monotonic()

    def wait(self, timeout: float = WAIT_S) -> int:
        try:
            return self.process.wait(timeout)
        finally:
            self.log_file.close()

    def close(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.log_file.close()


def ctl(out: Path, sock: Path, *args: str, timeout: float = 30) -> subprocess.CompletedProcess:
    """`supervisor.py ctl --control-socket SOCK ARGS...`, its output as text."""
    return subprocess.run(
        [PYTHON, str(out / "supervisor.py"), "ctl", "--control-socket", str(sock), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


# What begins every line of a node's log file, and of `ctl logs`: its time in ISO 8601 with the local offset, a space.
LOG_STAMP = r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}[+-]\d\d:\d\d "


def unstamped(line: str) -> str:
    """A line of a node's log without its time, which it must begin with."""
    stamp = re.match(LOG_STAMP, line)
    assert stamp, f"no time at the start of {line[:80]!r}"
    return line[stamp.end() :]


def log_times(text: str, pattern: str) -> list[float]:
    """The supervisor's timestamps of the log lines matching `pattern`."""
    return [float(m.group(1)) for m in re.finditer(r"^\[\s*([\d.]+)\] " + pattern, text, re.M)]


def kill_all(pids):
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
