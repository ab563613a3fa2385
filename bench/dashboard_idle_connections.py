"""Dashboard under clients that open connections and never finish a request (slowloris): answer time and output.

    .venv/bin/python bench/dashboard_idle_connections.py [--quick]

The dashboard server (python -m joshua_runtime.dashboard, on a joshuac build of a one-node description)
runs with the soft limit of open files a user session or a systemd service usually has (1024). This
process then opens N connections and holds them: half send part of a request head, half nothing. It
prints the answer time of GET /api/robot (with the token) before and while they are held, how many of
them the server closed after its head deadline, and how much the server wrote meanwhile. --quick: 200
connections, counted as soon as the server closed them all rather than after the deadline's margin.
"""

import argparse
import http.client
import resource
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from joshua_core.dashboard_token import token_path  # noqa: E402
from joshua_runtime.dashboard.connections import HEAD_TIMEOUT_S  # noqa: E402
from testsupport.joshuac_cli import joshuac  # noqa: E402

DESCRIPTION = """robot_config { name: "bench_idle" mode: MODE_TELEOPERATION
  node { name: "sleeper" type: CUSTOM executable: "/bin/sleep" args: ["600"] }
}
"""
USER_DEFAULT_NOFILE = 1024
SERVER_START_TIMEOUT_S = 60.0
REQUEST_TIMEOUT_S = 60.0
SAMPLES = 20
DEADLINE_MARGIN_S = 5.0  # waited beyond the head deadline before counting closed connections
CONNECTIONS, QUICK_CONNECTIONS = 3000, 200
POLL_S = 0.1


def answer_ms(port: int, token: str) -> float:
    start = time.perf_counter()
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=REQUEST_TIMEOUT_S)
    try:
        connection.request("GET", "/api/robot", headers={"Authorization": f"Bearer {token}"})
        response = connection.getresponse()
        response.read()
        if response.status != 200:
            raise SystemExit(f"GET /api/robot answered {response.status}")
    finally:
        connection.close()
    return (time.perf_counter() - start) * 1000


def median_answer_ms(port: int, token: str) -> float:
    """The median of SAMPLES answer times, after as many unmeasured requests (the first ones are slower)."""
    times = [answer_ms(port, token) for _ in range(2 * SAMPLES)]
    return statistics.median(times[SAMPLES:])


def hold_idle_connections(port: int, count: int) -> list[socket.socket]:
    held = []
    for index in range(count):
        connection = socket.socket()
        connection.settimeout(5)
        held.append(connection)
        try:
            connection.connect(("127.0.0.1", port))
            if index % 2:
                connection.sendall(b"GET /api/robot HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        except OSError:
            pass
    return held


def closed_by_server(connection: socket.socket) -> bool:
    try:
        return connection.recv(1, socket.MSG_DONTWAIT) == b""
    except BlockingIOError:
        return False
    except OSError:
        return True


def wait_closed(held: list[socket.socket], until: float, all_closed: bool) -> int:
    """How many of `held` the server closed by `until` (monotonic), or (`all_closed`) as soon as it closed all."""
    while all_closed and time.monotonic() < until:
        if all(closed_by_server(connection) for connection in held):
            return len(held)
        time.sleep(POLL_S)
    time.sleep(max(0.0, until - time.monotonic()))
    return sum(closed_by_server(connection) for connection in held)


def start_server(directory: Path, port: int, output: Path) -> subprocess.Popen:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (USER_DEFAULT_NOFILE, hard))  # inherited by the server
    try:
        with open(output, "w") as log:
            server = subprocess.Popen(
                [sys.executable, "-m", "joshua_runtime.dashboard", "--manifest", str(directory / "out" / "manifest.json"),
                 "--control-socket", str(directory / "none.sock"), "--port", str(port)],
                stdout=log, stderr=subprocess.STDOUT,
            )  # fmt: skip
    finally:
        resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # room for this process's connections
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return server
        except OSError:
            if time.monotonic() > deadline or server.poll() is not None:
                raise SystemExit(f"the dashboard server did not start:\n{output.read_text()}") from None
            time.sleep(0.2)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="200 connections, counted once all are closed")
    quick = parser.parse_args().quick
    count = QUICK_CONNECTIONS if quick else CONNECTIONS
    with tempfile.TemporaryDirectory(prefix="bench-idle-") as name:
        directory = Path(name)
        (directory / "bench_idle.pbtxt").write_text(DESCRIPTION)
        built = joshuac("build", directory / "bench_idle.pbtxt", "-o", directory / "out")
        if built.returncode != 0:
            raise SystemExit(built.stderr)
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        output = directory / "server.log"
        server = start_server(directory, port, output)
        try:
            token = token_path(directory / "none.sock").read_text().strip()
            alone = median_answer_ms(port, token)
            written = output.stat().st_size
            start = time.monotonic()
            held = hold_idle_connections(port, count)
            opened_s = time.monotonic() - start
            attacked = median_answer_ms(port, token)
            closed = wait_closed(held, start + HEAD_TIMEOUT_S + DEADLINE_MARGIN_S, all_closed=quick)
            growth = output.stat().st_size - written
            for connection in held:
                connection.close()
        finally:
            server.terminate()
            server.wait(10)
    print(f"server soft limit {USER_DEFAULT_NOFILE} open files; {count} idle connections opened in {opened_s:.1f} s")
    print(
        f"GET /api/robot median of {SAMPLES}: {alone:.1f} ms alone, {attacked:.1f} ms with the connections held "
        f"({attacked / alone:.2f}x)"
    )
    print(
        f"closed by the server within {HEAD_TIMEOUT_S + DEADLINE_MARGIN_S:.1f} s: {closed} of {count}; "
        f"server output meanwhile: {growth} bytes"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
