"""The control plane of a robot on two hosts of this machine: how fast it tells of trouble, and what a request to
another host costs.

    .venv/bin/python bench/hosts_control.py [--runs 3] [--requests 200] [--quick]

The robot of testsupport/split_robot.py (host arm: Discovery Server, leader, the router; host gpu: follower,
dashboard), each host's part under its own supervisor.py, joined by the agents over Zenoh with passwords.
- discovery: `ctl stop discovery_server` on arm, then `ctl status` on gpu polled every 0.1 s until it says the
  server is unreachable; against the bound of 5 s after the last answer (discovery/watch.py). The server is
  started again and reported reachable before the next run.
- silent host: `ctl stop host_agent_arm`, then the dashboard's /api/status on gpu polled until arm's
  processes are `unknown`; against HOST_SILENT_AFTER_S (3 s; agents publish every 1 s).
- requests: a `status` request to arm's supervisor through gpu's agent (Zenoh, passwords, the router on arm),
  against the same request on arm's own control socket, one connection each, in turns; medians and their ratio.
"""

import argparse
import json
import os
import socket
import statistics
import sys
import tempfile
import time
from pathlib import Path

from support.ros_env import bench_environment

from joshua_runtime.hosts.roster import HOST_SILENT_AFTER_S
from testsupport.split_robot import SplitRobot, password_credentials

WATCH_BOUND_S = 5.0  # discovery/watch.py: unreachable at most HEALTHY_PERIOD_S + UNREACHABLE_AFTER_S after an answer
POLL_S = 0.1
TIMEOUT_S = 60.0


def wait(predicate, what: str) -> float:
    """Seconds until `predicate()` holds, polled every POLL_S."""
    started = time.monotonic()
    while not predicate():
        if time.monotonic() - started > TIMEOUT_S:
            raise SystemExit(f"hosts_control: no {what} within {TIMEOUT_S:g} s")
        time.sleep(POLL_S)
    return time.monotonic() - started


def discovery_reachable(robot: SplitRobot):
    return robot.status("gpu")["discovery"]["reachable"]


def discovery_run(robot: SplitRobot) -> float:
    wait(lambda: discovery_reachable(robot) is True, "reachable Discovery Server")
    robot.ctl("arm", "stop", "discovery_server")
    taken = wait(lambda: discovery_reachable(robot) is False, "unreachable report")
    robot.ctl("arm", "start", "discovery_server")
    return taken


def arm_unknown(robot: SplitRobot) -> bool:
    nodes = robot.api("/api/status")["nodes"]
    return all(node["state"] == "unknown" for node in nodes if node["host"] == "arm")


def silence_run(robot: SplitRobot) -> float:
    wait(lambda: robot.api("/api/status")["hosts"][0]["reachable"], "host arm heard")
    robot.ctl("arm", "stop", "host_agent_arm")
    taken = wait(lambda: arm_unknown(robot), "arm's processes unknown")
    robot.ctl("arm", "start", "host_agent_arm")
    return taken


class LineClient:
    def __init__(self, path: Path):
        self.connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.connection.connect(str(path))
        self.replies = self.connection.makefile("rb")

    def ask(self, request: dict) -> float:
        started = time.perf_counter()
        self.connection.sendall(json.dumps(request).encode() + b"\n")
        reply = json.loads(self.replies.readline())
        assert reply.get("ok"), reply
        return time.perf_counter() - started


def request_costs(robot: SplitRobot, count: int) -> tuple[list[float], list[float]]:
    wait(lambda: robot.ctl("gpu", "--host", "arm", "status").returncode == 0, "arm answering through gpu's agent")
    local = LineClient(robot.control_socket("arm"))
    remote = LineClient(Path(str(robot.control_socket("gpu")).removesuffix(".sock") + ".hosts.sock"))
    local_s, remote_s = [], []
    for _ in range(count):
        local_s.append(local.ask({"command": "status"}))
        remote_s.append(remote.ask({"command": "status", "host": "arm"}))
    return local_s, remote_s


def figures(name: str, values: list[float], bound: float) -> str:
    median = statistics.median(values)
    return (
        f"{name}: median {median:.2f} s, max {max(values):.2f} s over {len(values)} runs; "
        f"{median / bound:.2f}x of the {bound:g} s bound"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--requests", type=int, default=200)
    parser.add_argument("--quick", action="store_true", help="one run, 20 requests")
    args = parser.parse_args()
    runs, requests = (1, 20) if args.quick else (args.runs, args.requests)
    with tempfile.TemporaryDirectory(prefix="hosts_control-") as scratch:
        directory = Path(scratch)
        env = bench_environment("hosts_control", XDG_RUNTIME_DIR=str(directory), XDG_STATE_HOME=str(directory))
        robot = SplitRobot(directory, password_credentials(directory / "credentials"), env)
        try:
            robot.start_all()
            robot.wait_for_dashboard()
            load = os.getloadavg()[0]
            local_s, remote_s = request_costs(robot, requests)
            discovery = [discovery_run(robot) for _ in range(runs)]
            silence = [silence_run(robot) for _ in range(runs)]
        finally:
            robot.stop_all()
    print(figures("Discovery Server stopped -> unreachable in gpu's ctl status", discovery, WATCH_BOUND_S))
    print(figures("agent of arm stopped -> arm's processes unknown on the dashboard", silence, HOST_SILENT_AFTER_S))
    local, remote = statistics.median(local_s) * 1000, statistics.median(remote_s) * 1000
    print(
        f"status of arm: {remote:.2f} ms through gpu's agent and Zenoh, {local:.2f} ms on arm's control socket "
        f"({remote / local:.2f}x), medians of {requests} each; load average {load:.1f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
