"""File descriptors: a thousand clients, descriptor numbers above 1023, and running out of descriptors
altogether neither crash the supervisor nor make it spin; its nodes get the limit it was started with."""

import json
import os
import resource
import signal
import socket
import subprocess
import time
from contextlib import ExitStack

from control_harness import RawClient, start_robot, status, talker_node
from supervisor_harness import PYTHON, WAIT_S, build, robot, wait_until

from joshua_codegen.supervisor.control import CONTROL_CLIENTS_MAX

CLOCK_TICKS = os.sysconf("SC_CLK_TCK")
SPIN_WATCH_S = 2.0  # how long the supervisor's CPU time is watched while it cannot accept
# A node that writes the RLIMIT_NOFILE it was started with, as JSON, to the file named by its argument.
LIMIT_REPORTER = (
    "import json, resource, sys, time\n"
    "with open(sys.argv[1], 'w') as out:\n    json.dump(resource.getrlimit(resource.RLIMIT_NOFILE), out)\n"
    "time.sleep(3600)\n"
)
# A node that runs until the file named by its argument exists, then fails.
FAIL_ON_TRIGGER = "import os, sys, time\nwhile not os.path.exists(sys.argv[1]):\n    time.sleep(0.02)\nsys.exit(1)\n"


def raise_own_fd_limit(wanted: int) -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < wanted:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(wanted, hard), hard))


def open_fds(pid: int) -> list[int]:
    return [int(name) for name in os.listdir(f"/proc/{pid}/fd")]


def cpu_seconds(pid: int) -> float:
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # utime, stime


def test_more_clients_than_the_cap_and_descriptors_above_1023_are_served(tmp_path):
    raise_own_fd_limit(CONTROL_CLIENTS_MAX + 200)
    out, sock, _, _, supervisor = start_robot(tmp_path)
    try:
        with ExitStack() as stack:
            idle = []
            for _ in range(CONTROL_CLIENTS_MAX - 1):
                client = stack.enter_context(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM))
                client.connect(str(sock))
                idle.append(client)
            wait_until(lambda: max(open_fds(supervisor.pid)) > 1023, "descriptors above 1023 in the supervisor")
            served = RawClient(sock)  # the last one under the cap
            assert served.request(b'{"command": "status"}\n')["ok"] is True
            refused = RawClient(sock)
            assert refused.reply() == {
                "ok": False,
                "kind": "busy",
                "error": f"too many control clients ({CONTROL_CLIENTS_MAX}); try again later",
            }
            assert refused.reply() is None
            refused.close()
            assert served.request(b'{"command": "restart", "node": "steady"}\n')["state"] == "running"
            served.close()
            assert supervisor.process.poll() is None
        # every idle client closed: their slots are free again
        assert status(tmp_path / "out", sock)["steady"]["state"] == "running"
    finally:
        supervisor.signal()
        code = supervisor.wait()
    assert code == 0
    assert "internal error" not in supervisor.log()


def test_out_of_descriptors_the_supervisor_backs_off_and_a_node_start_fails_like_a_node(tmp_path):
    trigger = tmp_path / "fail-now"
    flaky = talker_node(
        "flaky", FAIL_ON_TRIGGER, args=[str(trigger)], extra="restart: RESTART_ON_FAILURE max_restarts: 100"
    )
    out, sock, _, _, supervisor = start_robot(tmp_path, flaky)
    try:
        # Leave the supervisor a few descriptors to spare (as `prlimit` would), then take them with idle clients.
        spare = len(open_fds(supervisor.pid)) + 6
        resource.prlimit(supervisor.pid, resource.RLIMIT_NOFILE, (spare, spare))
        with ExitStack() as stack:
            for _ in range(20):
                client = stack.enter_context(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM))
                client.connect(str(sock))  # past the last descriptor, connections wait in the backlog
            supervisor.wait_log(r"supervisor: control socket: cannot accept a client \(Too many open files\)")
            trigger.touch()  # flaky fails; its restart finds no descriptor for its output pipe
            supervisor.wait_log(r"flaky: cannot start: .*Too many open files")
            supervisor.wait_log(r"flaky: restarting in [\d.]+ s \(restart 2 ")
            trigger.unlink()
            before = cpu_seconds(supervisor.pid)
            time.sleep(SPIN_WATCH_S)
            used = cpu_seconds(supervisor.pid) - before
            assert used < SPIN_WATCH_S / 4, f"the supervisor used {used:.2f} CPU-s in {SPIN_WATCH_S} s: it spins"
            assert supervisor.process.poll() is None
        # Descriptors free again: the socket accepts and the node starts again.
        wait_until(lambda: status(out, sock)["flaky"]["state"] == "running", "flaky to run again")
    finally:
        supervisor.signal()
        code = supervisor.wait()
    assert code == 0
    assert "internal error" not in supervisor.log()


def test_nodes_get_the_descriptor_limit_the_supervisor_was_started_with(tmp_path):
    limits = tmp_path / "limits.json"
    out = build(tmp_path, robot([talker_node("reporter", LIMIT_REPORTER, args=[str(limits)])]))
    started_with = (1024, 4096)
    log_path = tmp_path / "supervisor.log"
    with open(log_path, "w") as log:
        process = subprocess.Popen(
            [PYTHON, str(out / "supervisor.py"), "--control-socket", str(tmp_path / "run" / "r.sock")],
            stdout=log,
            stderr=subprocess.STDOUT,
            preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_NOFILE, started_with),  # noqa: PLW1509
        )
    try:
        wait_until(lambda: limits.exists() and limits.read_text(), "the node's limits")
        assert tuple(json.loads(limits.read_text())) == started_with
        # the supervisor itself raised its soft limit, for its clients
        assert resource.prlimit(process.pid, resource.RLIMIT_NOFILE) == (4096, 4096)
    finally:
        process.send_signal(signal.SIGINT)
        code = process.wait(WAIT_S)
    assert code == 0, log_path.read_text()
