"""A generated supervisor.py running CUSTOM nodes in a temporary directory, with its control socket, node logs and
status timer, for the benchmarks that load the supervisor itself."""

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from google.protobuf import text_format

from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.write import write_tree
from joshua_core.schema import RobotDescription

START_TIMEOUT_S = 30.0  # the supervisor's control socket must answer within this
STOP_TIMEOUT_S = 30.0
STATUS_LINE = re.compile(r"\[\s*([\d.]+)\] supervisor: status: ")  # node output may precede it on its line


def quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def python_node(name: str, program: str) -> str:
    """A CUSTOM node running the Python `program` (this interpreter, `-c`)."""
    return f'node {{ name: "{name}" type: CUSTOM executable: "{sys.executable}" args: ["-c", {quoted(program)}] }}'


class SupervisedRobot:
    """`with SupervisedRobot(nodes, status_interval) as robot:` builds robot "bench" of the node blocks `nodes`
    and runs its supervisor.py with `--status-interval` (the timer whose lateness is the loop's jitter)."""

    def __init__(self, nodes: list[str], status_interval: float):
        self.nodes = nodes
        self.status_interval = status_interval
        self.directory = Path(tempfile.mkdtemp(prefix="joshua-bench-supervisor-"))
        self.socket = self.directory / "run" / "bench.sock"
        self.log_path = self.directory / "supervisor.log"
        self.logs = self.directory / "logs"
        self.process = None

    def __enter__(self):
        description = (
            'robot_config { name: "bench" mode: MODE_TELEOPERATION shutdown { sigint_grace_s: 2 sigterm_grace_s: 1 }\n'
            + "\n".join(self.nodes)
            + "\n}"
        )
        out = self.directory / "out"
        write_tree(render(plan(text_format.Parse(description, RobotDescription()), "bench.pbtxt")), out)
        with open(self.log_path, "w") as log:
            self.process = subprocess.Popen(
                [
                    sys.executable,
                    str(out / "supervisor.py"),
                    "--control-socket",
                    str(self.socket),
                    "--log-dir",
                    str(self.logs),
                    "--status-interval",
                    str(self.status_interval),
                ],
                stdout=log,
                stderr=subprocess.STDOUT,
            )
        deadline = time.monotonic() + START_TIMEOUT_S
        while not self.answers():
            if self.process.poll() is not None or time.monotonic() > deadline:
                raise SystemExit(f"the supervisor did not serve its control socket:\n{self.log_path.read_text()}")
            time.sleep(0.05)
        return self

    def answers(self) -> bool:
        try:
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
                probe.settimeout(1.0)
                probe.connect(str(self.socket))
                probe.sendall(b'{"command": "status"}\n')
                return probe.recv(4096).startswith(b'{"ok": true')
        except OSError:
            return False

    def mark(self) -> int:
        """A place in the supervisor's log: the lines written after it are its next ones."""
        return self.log_path.stat().st_size

    def timer_lateness(self, start: int, end: int) -> list[float]:
        """How late each status timer fired between the log marks `start` and `end`, in seconds."""
        with open(self.log_path, "rb") as log:
            log.seek(start)
            text = log.read(end - start).decode(errors="replace")
        times = [float(t) for t in STATUS_LINE.findall(text)]
        # log times have 1 ms steps: a timer on time may look up to 1 ms early
        return [max(0.0, later - earlier - self.status_interval) for earlier, later in zip(times, times[1:])]

    def cpu_seconds(self) -> float:
        fields = Path(f"/proc/{self.process.pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def __exit__(self, *exc):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(STOP_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        shutil.rmtree(self.directory, ignore_errors=True)
