"""Whatever a client writes to the control socket, and however slowly it reads, the supervisor answers with
one error line at worst and its loop never stops: nodes keep running, output keeps draining, ctl answers."""

import socket

import pytest
from control_harness import RawClient, ctl, start_robot, status, talker_node
from supervisor_harness import WAIT_S, wait_until

from joshua_codegen.supervisor.control_connection import CONTROL_OUTPUT_LIMIT_BYTES
from joshua_codegen.supervisor.control_request import CONTROL_LOG_LINES_MAX, CONTROL_REQUEST_LIMIT

# (request line, a fragment of the one-line error it must get)
HOSTILE_LINES = [
    (b"[" * 2000 + b"]" * 2000, "nested deeper than"),  # deeper than Python's recursion limit
    (b'{"command": "status", "x": ' + b'{"a": ' * 500 + b"}" * 500 + b"}", "nested deeper than"),
    (b'{"command": "logs", "node": "steady", "lines": Infinity}', "not a finite number: Infinity"),
    (b'{"command": "logs", "node": "steady", "lines": -Infinity}', "not a finite number: -Infinity"),
    (b'{"command": "logs", "node": "steady", "lines": NaN}', "not a finite number: NaN"),
    (b'{"command": "logs", "node": "steady", "lines": 1e400}', "not a finite number: 1e400"),
    (b'{"command": "logs", "node": "steady", "lines": 1' + b"0" * 3000 + b"}", "number longer than"),
    (
        b'{"command": "logs", "node": "steady", "lines": -1}',
        f"lines must be a whole number from 0 to {CONTROL_LOG_LINES_MAX}",
    ),
    (b'{"command": "logs", "node": "steady", "lines": 2.5}', "lines must be a whole number"),
    (b'{"command": "logs", "node": "steady", "lines": "5"}', "lines must be a whole number"),
    (b'{"command": "logs", "node": "steady", "lines": true}', "lines must be a whole number"),
    (b'{"command": "logs", "node": "steady", "follow": 1}', "follow must be true or false"),
    (b'{"command": "logs", "node": ["steady"]}', "node must be a string"),
    (b'{"command": "restart"}', "restart needs a node"),
    (b'{"command": "status", "node": "steady"}', "unknown field 'node' for status"),
    (b'{"command": "status", "extra": {"a": [1]}}', "unknown field 'extra' for status"),
    (b'{"command": 5}', "command must be one of"),
    (b'{"command": "reboot"}', "unknown command 'reboot'"),
    (b"{}", "command must be one of"),
    (b"[]", "a request is one JSON object"),
    (b'"status"', "a request is one JSON object"),
    (b"\xff\xfe{}", "not UTF-8"),
    (b'{"command": "status"', "not JSON"),
    (b"", "not JSON"),
]


@pytest.fixture
def robot(tmp_path):
    out, sock, logs, log, supervisor = start_robot(tmp_path)
    yield out, sock, supervisor
    supervisor.signal()
    assert supervisor.wait() == 0


def test_every_hostile_request_line_gets_one_error_line_and_the_robot_runs_on(robot):
    out, sock, supervisor = robot
    pid = status(out, sock)["steady"]["pid"]
    client = RawClient(sock)
    try:
        for line, error in HOSTILE_LINES:
            reply = client.request(line + b"\n")
            assert reply is not None, f"the supervisor closed the connection after {line[:60]!r}"
            assert reply["ok"] is False and reply["kind"] == "bad_request" and error in reply["error"], (
                line[:60],
                reply,
            )
            assert "\n" not in reply["error"] and len(reply["error"]) < 300
        assert client.request(b'{"command": "status"}\n')["ok"] is True  # the same connection still serves
    finally:
        client.close()
    assert supervisor.process.poll() is None
    assert status(out, sock)["steady"]["pid"] == pid
    assert "internal error" not in supervisor.log()


@pytest.mark.parametrize(
    "line", [b"[" * 30000 + b"\n", b" " * (CONTROL_REQUEST_LIMIT + 1)], ids=["30000 brackets", "no newline yet"]
)
def test_a_request_line_over_the_limit_is_refused_and_its_connection_closed(robot, line):
    out, sock, supervisor = robot
    client = RawClient(sock)
    try:
        client.send(line)
        reply = client.reply()
        assert reply == {
            "ok": False,
            "kind": "bad_request",
            "error": f"request line longer than {CONTROL_REQUEST_LIMIT} bytes",
        }
        assert client.reply() is None
    finally:
        client.close()
    assert status(out, sock)["steady"]["state"] == "running"


# Writes 20000 numbered lines of 60 bytes at once, then one line every 20 ms: a `logs` reply of the last
# 10000 lines is about 650 kB, more than a socket buffer holds.
CHATTY = (
    "import itertools, time\nfor n in range(20000):\n    print(f'{n:08d} ' + 'x' * 51)\n"
    "print('burst done', flush=True)\nfor n in itertools.count():\n"
    "    print(f'tick {n}', flush=True)\n    time.sleep(0.02)\n"
)
STALLED_CLIENTS = 30
REPLY_BYTES = 600_000  # the least a reply of the last 10000 of those lines takes
STALLED_REQUESTS = CONTROL_OUTPUT_LIMIT_BYTES // REPLY_BYTES + 2  # together past a client's buffer limit
DROPS_WAIT_S = 60.0  # hundreds of 1 MiB replies take the supervisor seconds on a busy machine (no timing here)


def test_clients_that_never_read_their_logs_replies_are_dropped_and_never_stall_the_loop(tmp_path):
    out, sock, logs, _, supervisor = start_robot(tmp_path, talker_node("chatty", CHATTY))
    stalled = []
    try:
        wait_until(
            lambda: (logs / "chatty.log").exists() and b"burst done" in (logs / "chatty.log").read_bytes(),
            "the burst in chatty's log",
        )
        request = f'{{"command": "logs", "node": "chatty", "lines": {CONTROL_LOG_LINES_MAX}}}\n'.encode()
        for _ in range(STALLED_CLIENTS):
            client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            client.connect(str(sock))
            client.sendall(request * STALLED_REQUESTS)
            stalled.append(client)
        ticks = (logs / "chatty.log").read_text().count("tick ")
        # The loop serves everyone else at once (before: 1 s of blocking per stalled client, 30 s in all).
        answered = ctl(out, sock, "status", timeout=WAIT_S)
        assert answered.returncode == 0, answered.stderr
        restarted = ctl(out, sock, "restart", "steady", timeout=WAIT_S)
        assert restarted.returncode == 0, restarted.stderr
        wait_until(lambda: (logs / "chatty.log").read_text().count("tick ") > ticks + 5, "chatty's output to drain")
        # Counted, not matched: a pattern repeated 30 times over a long log backtracks for minutes while fewer are in.
        wait_until(
            lambda: supervisor.log().count("dropped a client ") >= STALLED_CLIENTS,
            f"{STALLED_CLIENTS} clients dropped",
            timeout=DROPS_WAIT_S,
        )
        for client in stalled:  # each was closed: after what the kernel held, end of file
            client.settimeout(WAIT_S)
            received = 0
            while chunk := client.recv(1 << 20):
                received += len(chunk)
            assert received < STALLED_REQUESTS * REPLY_BYTES
    finally:
        for client in stalled:
            client.close()
        supervisor.signal()
        code = supervisor.wait()
    assert code == 0
    assert "internal error" not in supervisor.log()


def test_logs_of_a_node_whose_output_is_not_kept_is_an_error_line(tmp_path):
    out, sock, _, _, supervisor = start_robot(tmp_path, args=("--log-dir", ""))
    try:
        answered = ctl(out, sock, "logs", "steady")
        assert (answered.returncode, answered.stderr) == (
            1,
            "supervisor.py ctl: error: the output of steady is not kept (no log directory)\n",
        )
        assert status(out, sock)["steady"]["state"] == "running"
    finally:
        supervisor.signal()
        assert supervisor.wait() == 0
