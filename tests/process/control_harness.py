"""Drive a generated supervisor's control socket: through its `ctl` client, or as a raw socket peer."""

import json
import socket
import subprocess
import sys
from pathlib import Path

from supervisor_harness import PYTHON, WAIT_S, Supervisor, build, custom_node, quoted, robot

# A node that prints a numbered line to stdout every 50 ms.
TALKER = (
    "import itertools, sys, time\nfor n in itertools.count():\n    print(f'line {n}', flush=True)\n"
    "    time.sleep(0.05)\n"
)


def talker_node(name: str = "talker", program: str = TALKER, args: list[str] = (), extra: str = "") -> str:
    """A CUSTOM node running the Python `program` with `args` (TALKER by default); `extra` adds fields."""
    quoted_args = ", ".join(quoted(arg) for arg in ["-c", program, *args])
    return f'node {{ name: "{name}" type: CUSTOM executable: "{PYTHON}" args: [{quoted_args}] {extra} }}'


def ctl(out: Path, sock: Path, *args: str, timeout: float = 30) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(out / "supervisor.py"), "ctl", "--control-socket", str(sock), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def status(out: Path, sock: Path) -> dict:
    result = ctl(out, sock, "status", "--json")
    assert result.returncode == 0, result.stderr
    return {node["name"]: node for node in json.loads(result.stdout)["nodes"]}


def start_robot(tmp_path: Path, *nodes: str, args: tuple[str, ...] = ()):
    """A robot of a `steady` node and `nodes`, its control socket in tmp_path/run and its logs in tmp_path/logs:
    (out, socket, logs, events log, Supervisor)."""
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("steady", log), *nodes]))
    sock, logs = tmp_path / "run" / "r.sock", tmp_path / "logs"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(logs), *args)
    supervisor.wait_log(r"started: \d+ of \d+ nodes running")
    return out, sock, logs, log, supervisor


class RawClient:
    """One connection to a control socket, sending whatever bytes it is given."""

    def __init__(self, sock: Path, timeout: float = WAIT_S):
        self.connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.connection.settimeout(timeout)
        self.connection.connect(str(sock))
        self.replies = self.connection.makefile("rb")

    def send(self, data: bytes) -> None:
        self.connection.sendall(data)

    def reply(self) -> dict | None:
        """The next reply line, or None once the supervisor closed the connection."""
        line = self.replies.readline()
        return json.loads(line) if line else None

    def request(self, data: bytes) -> dict | None:
        self.send(data)
        return self.reply()

    def close(self) -> None:
        self.replies.close()
        self.connection.close()


__all__ = ["RawClient", "Supervisor", "build", "ctl", "start_robot", "status", "talker_node"]
