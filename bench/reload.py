"""`joshuac run --watch`: from saving the description to the changed node running (and ready) again, against a
`ctl restart` of that node and a full restart of the robot measured in the same run; and that the other nodes'
pids stayed.

    .venv/bin/python bench/reload.py [--quick]        # --quick: 2 saves, 1 of each floor (for the tests)

The robot is three runtime nodes (rclpy, mock devices; see DESCRIPTION): a `leader` encoder, a `follower`
actuator and a `camera`. Each save changes the leader's rate_hz (its
settings); the time runs from the rename that saves the file to the status of the control socket (polled every
POLL_S) showing a new leader pid that said READY=1. `ctl restart leader` runs from the request to the same; a
full restart from SIGINT to `joshuac run` (the cascade, then a new run: build, preflight, every node started)
to the same. Medians in seconds.
"""

import argparse
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))

from support.ros_env import bench_environment  # noqa: E402

SAVES, QUICK_SAVES = 6, 2
FLOORS, QUICK_FLOORS = 3, 1
POLL_S = 0.01
WAIT_S = 120.0  # for one node to be ready again; only ends a hang
ROBOT = "reload_bench"


def description(rate: int) -> str:
    return f"""robot_config {{
  name: "{ROBOT}"
  mode: MODE_TELEOPERATION
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader" rate_hz: {rate} }}
  node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader" }}
  node {{ name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera" width: 64 height: 48 }}
}}
"""


class WatchedRobot:
    """`joshuac run CONFIG --watch` in `directory`, with its own control socket and log directory."""

    def __init__(self, directory: Path, env: dict[str, str]):
        self.directory = directory
        self.config = directory / "robot.pbtxt"
        self.env = env
        self.socket = Path(env["XDG_RUNTIME_DIR"]) / "joshua" / f"{ROBOT}.sock"
        self.process = None

    def start(self) -> None:
        with open(self.directory / "joshuac.out", "a") as output:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "joshua_codegen", "run", str(self.config), "--watch"],
                cwd=self.directory,
                env=self.env,
                stdout=output,
                stderr=subprocess.STDOUT,
            )

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            self.process.wait(WAIT_S)

    def save(self, text: str) -> float:
        """Save the description as editors do (a new file renamed over it); when it was saved."""
        saved = self.config.with_name("robot.pbtxt.new")
        saved.write_text(text)
        os.replace(saved, self.config)
        return time.monotonic()

    def request(self, request: dict) -> dict | None:
        try:
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as connection:
                connection.settimeout(WAIT_S)
                connection.connect(str(self.socket))
                connection.sendall(json.dumps(request).encode() + b"\n")
                return json.loads(connection.makefile("rb").readline())
        except (OSError, ValueError):
            return None  # not serving (yet, or any more)

    def nodes(self) -> dict[str, dict]:
        reply = self.request({"command": "status"}) or {"nodes": []}
        return {node["name"]: node for node in reply["nodes"]}

    def ready_again(self, name: str, old_pid: int | None) -> tuple[float, dict[str, dict]]:
        """Wait until node `name` runs with a pid other than `old_pid` and is ready: when, and every node then."""
        deadline = time.monotonic() + WAIT_S
        while time.monotonic() < deadline:
            nodes = self.nodes()
            node = nodes.get(name)
            if node and node["pid"] not in (None, old_pid) and node["ready"] and node["state"] == "running":
                return time.monotonic(), nodes
            time.sleep(POLL_S)
        raise SystemExit(f"{name} was not ready again within {WAIT_S} s:\n{self.output()[-3000:]}")

    def all_ready(self) -> dict[str, dict]:
        deadline = time.monotonic() + WAIT_S
        while time.monotonic() < deadline:
            nodes = self.nodes()
            if len(nodes) == 3 and all(node["ready"] for node in nodes.values()):
                return nodes
            time.sleep(POLL_S)
        raise SystemExit(f"the robot was not ready within {WAIT_S} s:\n{self.output()[-3000:]}")

    def output(self) -> str:
        return (self.directory / "joshuac.out").read_text(errors="replace")


def measure(robot: WatchedRobot, saves: int, floors: int) -> None:
    robot.config.write_text(description(20))
    robot.start()
    nodes = robot.all_ready()
    reloads, kept, others = [], 0, 0
    for index in range(saves):
        before = {name: node["pid"] for name, node in nodes.items()}
        saved = robot.save(description(25 if index % 2 == 0 else 20))
        ready, nodes = robot.ready_again("leader", before["leader"])
        reloads.append(ready - saved)
        nodes = robot.all_ready()
        kept += sum(nodes[name]["pid"] == pid for name, pid in before.items() if name != "leader")
        others += len(before) - 1
    restarts = []
    for _ in range(floors):
        old = nodes["leader"]["pid"]
        asked = time.monotonic()
        robot.request({"command": "restart", "node": "leader"})
        ready, nodes = robot.ready_again("leader", old)
        restarts.append(ready - asked)
        nodes = robot.all_ready()
    full = []
    for _ in range(floors):
        old = nodes["leader"]["pid"]
        asked = time.monotonic()
        robot.stop()
        robot.start()
        ready, nodes = robot.ready_again("leader", old)
        full.append(ready - asked)
        nodes = robot.all_ready()
    robot.stop()
    reload, restart, whole = (statistics.median(times) for times in (reloads, restarts, full))
    print(
        f"save -> changed node ready again (--watch): median {reload:.3f} s of {saves} saves (max {max(reloads):.3f} s)"
    )
    print(f"other nodes' pids kept across those reloads: {kept} of {others} ({kept / others:.2f})")
    print(f"floor, ctl restart of that node -> ready: median {restart:.3f} s of {floors}")
    print(
        f"floor, full restart of the robot (SIGINT, joshuac run) -> that node ready: median {whole:.3f} s of {floors}"
    )
    print(f"ratio to ctl restart: {reload / restart:.2f}; to a full restart: {reload / whole:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 saves and 1 of each floor (for the tests)")
    options = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="joshua-bench-reload-") as temporary:
        directory = Path(temporary)
        for name in ("run", "state"):
            (directory / name).mkdir(mode=0o700)
        env = bench_environment(
            "reload", XDG_RUNTIME_DIR=str(directory / "run"), XDG_STATE_HOME=str(directory / "state")
        )
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH", "")]))
        robot = WatchedRobot(directory, env)
        try:
            measure(robot, QUICK_SAVES if options.quick else SAVES, QUICK_FLOORS if options.quick else FLOORS)
        finally:
            if robot.process is not None and robot.process.poll() is None:
                robot.process.kill()
                robot.process.wait()


if __name__ == "__main__":
    main()
