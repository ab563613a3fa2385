"""What the control socket answers and `ctl` exits with: the same for every refusal of one kind, the kind named in
the reply; unplanned restarts counted apart from the restarts asked for."""

import os
import signal

from control_harness import RawClient, ctl, start_robot, status, talker_node
from supervisor_harness import Supervisor, build, custom_node, events, robot, wait_until

# Exits 1 at its first start (creating the file named by its argument), runs from its second on.
FAILS_ONCE = "import os, sys, time\nif not os.path.exists(sys.argv[1]):\n    open(sys.argv[1], 'w').close()\n    sys.exit(1)\ntime.sleep(3600)\n"


def test_stop_of_a_stopped_node_and_start_of_a_running_one_are_both_conflicts_exit_1(tmp_path):
    out, sock, _, _, supervisor = start_robot(tmp_path)
    client = RawClient(sock)
    try:
        assert ctl(out, sock, "stop", "steady").returncode == 0
        again = ctl(out, sock, "stop", "steady")
        assert (again.returncode, again.stdout, again.stderr) == (
            1,
            "",
            "supervisor.py ctl: error: steady is already stopped\n",
        )
        assert client.request(b'{"command": "stop", "node": "steady"}\n') == {
            "ok": False,
            "kind": "conflict",
            "error": "steady is already stopped",
        }
        assert ctl(out, sock, "start", "steady").returncode == 0
        running = ctl(out, sock, "start", "steady")
        assert (running.returncode, running.stdout, running.stderr) == (
            1,
            "",
            "supervisor.py ctl: error: steady is already running\n",
        )
        assert client.request(b'{"command": "start", "node": "steady"}\n') == {
            "ok": False,
            "kind": "conflict",
            "error": "steady is already running",
        }
    finally:
        client.close()
        supervisor.signal()
        assert supervisor.wait() == 0


def test_each_refusal_names_its_kind_and_ctl_exit_codes_follow_the_table(tmp_path):
    out, sock, _, _, supervisor = start_robot(tmp_path)
    client = RawClient(sock)
    try:
        assert client.request(b'{"command": "restart", "node": "nobody"}\n') == {
            "ok": False,
            "kind": "not_found",
            "error": "no node named 'nobody'",
        }
        refused = client.request(b'{"command": "reboot"}\n')
        assert refused["kind"] == "bad_request" and refused["ok"] is False
        assert ctl(out, sock, "restart", "nobody").returncode == 1
        assert ctl(out, sock, "logs", "steady", "-n", "-1").returncode == 2  # usage: checked before sending
        assert ctl(out, sock, "logs", "steady", "-n", "10001").returncode == 2
        assert ctl(out, sock, "reboot").returncode == 2
        assert ctl(out, sock, "status").returncode == 0
    finally:
        client.close()
        supervisor.signal()
        assert supervisor.wait() == 0
    gone = ctl(out, sock, "status")
    assert gone.returncode == 3 and gone.stderr.startswith(f"supervisor.py ctl: error: control socket {sock}: ")
    assert ctl(out, tmp_path / "nowhere" / "r.sock", "stop", "steady").returncode == 3


def test_requests_while_the_robot_stops_are_refused_as_stopping(tmp_path):
    log = tmp_path / "events.log"
    # The robot stops for as long as the stubborn node ignores SIGINT: until a second SIGINT moves on to SIGTERM.
    out = build(tmp_path, robot([custom_node("steady", log), custom_node("stubborn", log, "SIGINT=ignore")], sigint=60))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(tmp_path / "logs"))
    client = None
    try:
        supervisor.wait_log(r"started: 2 of 2 nodes running")
        wait_until(
            lambda: {name for name, _, text in events(log) if text == "start"} == {"steady", "stubborn"}, "handlers"
        )
        client = RawClient(sock)
        os.kill(supervisor.pid, signal.SIGINT)
        supervisor.wait_log(r"received SIGINT: stopping every node")
        assert client.request(b'{"command": "start", "node": "steady"}\n') == {
            "ok": False,
            "kind": "stopping",
            "error": "the robot is stopping",
        }
    finally:
        if client is not None:
            client.close()
        supervisor.signal()  # the second SIGINT: SIGTERM for the stubborn node
        supervisor.wait()


def test_restarts_count_the_policys_restarts_and_manual_restarts_those_asked_for(tmp_path):
    once = talker_node("once", FAILS_ONCE, args=[str(tmp_path / "failed-once")], extra="restart: RESTART_ON_FAILURE")
    out, sock, _, _, supervisor = start_robot(tmp_path, once)
    try:
        supervisor.wait_log(r"once: restarting in [\d.]+ s \(restart 1 of")
        supervisor.wait_log(r"(?s)once: started pid .*once: started pid ")
        counted = status(out, sock)["once"]
        assert (counted["restarts"], counted["manual_restarts"]) == (1, 0)
        assert ctl(out, sock, "restart", "once").returncode == 0
        assert ctl(out, sock, "restart", "steady").returncode == 0
        nodes = status(out, sock)
        assert (nodes["once"]["restarts"], nodes["once"]["manual_restarts"]) == (1, 1)
        assert (nodes["steady"]["restarts"], nodes["steady"]["manual_restarts"]) == (0, 1)
        shown = ctl(out, sock, "status").stdout
        assert "0 restarts, 1 asked for" in shown and "1 restarts, 1 asked for" in shown
    finally:
        supervisor.signal()
        assert supervisor.wait() == 0
