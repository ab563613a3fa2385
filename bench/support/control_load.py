"""Control-socket requests/s and the supervisor loop's timer lateness with 1000 idle clients connected and with 30
clients that never read their `logs` replies, each against the same loop with no other client (the floor)."""

import json
import os
import socket
import statistics
import subprocess
import sys
import time
from contextlib import ExitStack, contextmanager

from support.supervised_robot import SupervisedRobot, python_node

IDLE_CLIENTS = 1000
STALLED_CLIENTS = 30
LOG_LINES = 10000
STATUS_INTERVAL_S = 0.05  # the supervisor's status timer, whose lateness is the loop's jitter
JITTER_TARGET_S = 0.050
PHASE_S, QUICK_PHASE_S = 4.0, 0.5  # a quick phase still sees 10 ticks of the status timer
ROUNDS, QUICK_ROUNDS = 3, 1  # the phases run in turn this many times (the machine's other load varies)
REPLY_TIMEOUT_S = 10.0
# 20000 lines of 100 bytes at once (a `logs` reply of the last 10000 is the 1 MiB the supervisor reads at
# most), then 500 lines a second, which every stalled client follows.
CHATTY = (
    "import itertools, time\nfor n in range(20000):\n    print(f'{n:08d} ' + 'x' * 91)\n"
    "print('burst done', flush=True)\nfor n in itertools.count():\n"
    "    print(f'{n:08d} ' + 'y' * 91, flush=True)\n    time.sleep(0.002)\n"
)


# Holds the clients of one phase in a process of their own (so the measuring client's process is the same in
# every phase): argv: socket path, count, request line to send or "" (idle); prints "ready" once all are
# connected, keeps them until its stdin closes. Never reads a reply.
CLIENTS = r"""
import resource, socket, sys
path, count, request = sys.argv[1], int(sys.argv[2]), sys.argv[3].encode()
soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, count + 100), hard))
connections = []
for _ in range(count):
    connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    connection.connect(path)  # blocking: waits while the socket's queue is full
    if request:
        connection.sendall(request)
    connections.append(connection)
print("ready", flush=True)
sys.stdin.read()
"""


def connect(path) -> socket.socket:
    """A connection to the socket at `path`; a blocking connect waits while the socket's queue is full."""
    connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    connection.connect(str(path))
    connection.settimeout(REPLY_TIMEOUT_S)
    return connection


def status_round_trips(path, seconds: float) -> float:
    """Sequential status requests on one connection for `seconds`: requests per second."""
    with connect(path) as connection:
        replies = connection.makefile("rb")
        count, started = 0, time.monotonic()
        while time.monotonic() - started < seconds:
            connection.sendall(b'{"command": "status"}\n')
            if not json.loads(replies.readline())["ok"]:
                raise SystemExit("the supervisor refused a status request")
            count += 1
        return count / (time.monotonic() - started)


@contextmanager
def held_clients(path, count: int, request: str = ""):
    """`count` connections to `path` held by another process, each having sent `request` (if any)."""
    holder = subprocess.Popen(
        [sys.executable, "-c", CLIENTS, str(path), str(count), request],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        if holder.stdout.readline() != "ready\n":
            raise SystemExit(f"the process holding {count} clients failed")
        yield
    finally:
        holder.stdin.close()
        holder.wait(REPLY_TIMEOUT_S)


def phase(robot: SupervisedRobot, seconds: float, clients) -> tuple[float, list[float], float]:
    """Once `clients` (a context manager) are connected: the status timer's lateness (in s) while the loop has
    only them and the node to serve, then requests/s on one more connection, and the supervisor's CPU-s over
    both."""
    with clients:
        start, cpu = robot.mark(), robot.cpu_seconds()
        time.sleep(seconds)
        lateness = robot.timer_lateness(start, robot.mark())
        rate = status_round_trips(robot.socket, seconds)
        cpu = robot.cpu_seconds() - cpu
    return rate, lateness, cpu


def wait_for_burst(log_file) -> None:
    deadline = time.monotonic() + REPLY_TIMEOUT_S
    while not (log_file.exists() and b"burst done" in log_file.read_bytes()):
        if time.monotonic() > deadline:
            raise SystemExit("the chatty node did not write its burst")
        time.sleep(0.05)


def measure(quick: bool) -> None:
    seconds, rounds = (QUICK_PHASE_S, QUICK_ROUNDS) if quick else (PHASE_S, ROUNDS)
    # each stalled client asks for the last LOG_LINES lines of the node (1 MiB) and to follow it, and never
    # reads: 30 MiB of replies in all, under the supervisor's limits (8 MiB a client, 64 MiB in all)
    stalled = json.dumps({"command": "logs", "node": "chatty", "lines": LOG_LINES, "follow": True}) + "\n"
    phases = {
        "no other client (floor)": lambda robot: ExitStack(),
        f"{IDLE_CLIENTS} idle clients": lambda robot: held_clients(robot.socket, IDLE_CLIENTS),
        f"{STALLED_CLIENTS} stalled clients": lambda robot: held_clients(robot.socket, STALLED_CLIENTS, stalled),
    }
    results = {name: [] for name in phases}
    with SupervisedRobot([python_node("chatty", CHATTY)], STATUS_INTERVAL_S) as robot:
        wait_for_burst(robot.logs / "chatty.log")
        for _ in range(rounds):
            for name, hold in phases.items():
                results[name].append(phase(robot, seconds, hold(robot)))
        dropped = robot.log_path.read_text().count("dropped a client")
    print(
        f"control socket, robot with a node writing 500 lines/s (stalled clients follow it); each phase "
        f"{rounds} x ({seconds:g} s for the supervisor's {STATUS_INTERVAL_S * 1000:.0f} ms status timer, whose "
        f"lateness is the loop's jitter, then {seconds:g} s of status requests on one more connection)"
    )
    print(
        f"{'phase':<26} {'requests/s':>11} {'vs floor':>9} {'timer late p50':>15} {'p99':>9} {'max':>9} "
        f"{'CPU':>7}  target (max)"
    )
    floor = statistics.median(rate for rate, _, _ in results["no other client (floor)"])
    for name, runs in results.items():
        rate = statistics.median(rate for rate, _, _ in runs)
        lateness = sorted(late for _, lates, _ in runs for late in lates) or [0.0]
        cpu = sum(cpu for _, _, cpu in runs) / (rounds * seconds * 2)
        worst = lateness[-1]
        print(
            f"{name:<26} {rate:11.1f} {rate / floor:8.2f}x {statistics.median(lateness) * 1000:12.1f} ms "
            f"{lateness[int(0.99 * (len(lateness) - 1))] * 1000:6.1f} ms {worst * 1000:6.1f} ms {cpu * 100:6.1f}%  "
            f"{'met' if worst < JITTER_TARGET_S else 'MISSED'} (< {JITTER_TARGET_S * 1000:.0f} ms)"
        )
    print(
        f"stalled clients dropped for leaving too much unread: {dropped}; machine load average (1 min) at the end: "
        f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"
    )
