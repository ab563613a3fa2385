"""The fleet server's memory under junk: `joshua-fleet` in a process of its own, a Zenoh peer that
publishes rounds of junk keys, and the server's RSS idle (the floor), at its peak, and after each round
once the junk is forgotten: flat when the later rounds leave it where the first did.

The junk, one key each, `joshua/junk_<i>/status`, in turn: the largest status the schema admits (256
nodes, just under 64 KiB), a status over 64 KiB, JSON of the wrong shape (`[1,2,3]`, `"nodes": "abc"`, a
`javascript:` link) and a key that names no robot.
"""

import json
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SERVER_START_TIMEOUT_S = 60.0
SETTLE_S = 1.0  # after the server started, and after the roster emptied, before RSS is read
SAMPLE_PERIOD_S = 0.05
POLL_S = 0.2
DRAIN_TIMEOUT_S = 300.0
OFFLINE_AFTER_S = 1.0
MARKER = "bench_marker"  # a robot known before the junk: its update, put last, tells when all was handled
MARKER_EVERY = 200  # junk keys between two statuses of the marker
MIB = 1024 * 1024


@dataclass(frozen=True)
class FleetMemory:
    keys_per_round: int
    floor_mib: float  # the idle server, one robot known
    peak_mib: float  # the highest RSS while junk arrived and was handled
    after_rounds_mib: tuple[float, ...]  # after each round's junk was forgotten
    most_robots: int  # the longest list /api/robots gave during the run
    keys_per_s: float  # junk keys handled per second, first round

    def summary(self) -> str:
        rounds = len(self.after_rounds_mib)
        after = " / ".join(f"{mib:.1f}" for mib in self.after_rounds_mib)
        last = self.after_rounds_mib[-1]
        return (
            f"fleet server RSS, {rounds} rounds of {self.keys_per_round} junk keys ({rounds * self.keys_per_round} "
            f"in all): floor (idle) {self.floor_mib:.1f} MiB; peak {self.peak_mib:.1f} MiB "
            f"({self.peak_mib / self.floor_mib:.2f}x floor); after each round's eviction {after} MiB; last "
            f"{last / self.floor_mib:.2f}x floor ({last - self.floor_mib:+.1f} MiB), "
            f"{last - self.after_rounds_mib[0]:+.1f} MiB since the first round; at most {self.most_robots} robots "
            f"listed; {self.keys_per_s:.0f} keys/s handled"
        )


KEYS, ROUNDS = 5000, 4  # 20000 junk keys in all
QUICK_KEYS, QUICK_ROUNDS = 400, 2  # past MARKER_EVERY, so the marker is put between junk keys too
FORGET_AFTER_S, QUICK_FORGET_AFTER_S = 5.0, 1.5  # both longer than OFFLINE_AFTER_S, as the server requires
QUICK_SETTLE_S = 0.2


def measure(quick: bool = False) -> FleetMemory:
    """Print and return the figures of one run (when `quick` 2 rounds of 400 keys, forgotten after 1.5 s and
    settling 0.2 s; else 4 of 5000, forgotten after 5 s)."""
    if quick:
        result = fleet_memory(QUICK_KEYS, QUICK_ROUNDS, QUICK_FORGET_AFTER_S, QUICK_SETTLE_S)
    else:
        result = fleet_memory(KEYS, ROUNDS)
    print(result.summary(), flush=True)
    return result


def fleet_memory(
    keys: int, rounds: int = ROUNDS, forget_after_s: float = FORGET_AFTER_S, settle_s: float = SETTLE_S
) -> FleetMemory:
    """Run the measurement on a fresh fleet server: `rounds` times, `keys` junk keys then their eviction
    (`forget_after_s`); RSS idle before, at the peak, and after each eviction (each read `settle_s` after)."""
    endpoint, http_port = f"tcp/127.0.0.1:{_free_port()}", _free_port()
    log = tempfile.TemporaryFile("w+")
    server = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.dashboard.fleet", "--listen", endpoint, "--port", str(http_port)]
        + ["--offline-after", str(OFFLINE_AFTER_S), "--forget-after", str(forget_after_s)]
        + ["--rollout-state", os.devnull],  # robots of a rollout recorded on this machine are not listed
        stdout=log,
        stderr=subprocess.STDOUT,
        cwd=ROOT,
    )
    api = f"http://127.0.0.1:{http_port}/api/robots"
    most = 0

    def note(robots: list) -> None:
        nonlocal most
        most = max(most, len(robots))

    try:
        _wait_answering(api, server)
        with _peer(endpoint) as peer:
            peer.put(f"joshua/{MARKER}/status", _status(MARKER, 1))
            _wait_listed(api, lambda robots: any(r["name"] == MARKER for r in robots))
            time.sleep(settle_s)
            floor = _rss_mib(server.pid)
            sampler = _Sampler(server.pid)
            after, speeds = [], []
            for round_number in range(rounds):
                started = time.monotonic()
                for index in range(keys):
                    if index % MARKER_EVERY == 0:  # known before the roster fills, and never forgotten
                        peer.put(f"joshua/{MARKER}/status", _status(MARKER, 1))
                    peer.put(*_junk(index))
                done = f"round {round_number}"
                peer.put(f"joshua/{MARKER}/status", _status(MARKER, 1, error=done))
                _wait_listed(api, lambda robots, done=done: any(r["error"] == done for r in robots), note)
                speeds.append(keys / (time.monotonic() - started))
                _wait_listed(api, lambda robots: not robots, note)
                time.sleep(settle_s)
                after.append(_rss_mib(server.pid))
            sampler.stop()
        return FleetMemory(keys, floor, max(sampler.peak, floor), tuple(after), most, speeds[0])
    except Exception:
        log.seek(0)
        print(f"joshua-fleet (exit {server.poll()}) wrote:\n{log.read()}", file=sys.stderr)
        raise
    finally:
        server.terminate()
        server.wait(10)
        log.close()


def _junk(index: int) -> tuple[str, bytes | str]:
    name = f"junk_{index}"
    kind = index % 6
    if kind == 0:
        return f"joshua/{name}/status", _largest_status(name)
    if kind == 1:
        return f"joshua/{name}/status", json.dumps({"nodes": [], "error": "x" * (96 * 1024)})
    if kind == 2:
        return f"joshua/{name}/status", "[1,2,3]"
    if kind == 3:
        return f"joshua/{name}/status", '{"nodes": "abc"}'
    if kind == 4:
        return f"joshua/{name}/status", json.dumps({"nodes": [], "url": "javascript:alert(1)"})
    return f"joshua/Junk-{index}/status", _status(name, 1)


def _largest_status(name: str) -> str:
    """256 nodes whose names fill the status to just under 64 KiB."""
    nodes = 256
    base = len(_status(name, nodes, node_name=""))
    return _status(name, nodes, node_name="n" * ((63 * 1024 - base) // nodes))


def _status(robot: str, nodes: int, node_name: str = "node", error: str | None = None) -> str:
    entries = [
        {"name": f"{node_name}{i}", "state": "running", "pid": 1000 + i, "restarts": 0, "ready": True, "since_s": 1.5}
        for i in range(nodes)
    ]
    return json.dumps({"robot": robot, "nodes": entries, "url": f"http://{robot}.example:8640/", "error": error})


class _Sampler:
    """The highest RSS of a process, sampled from a thread until stop()."""

    def __init__(self, pid: int):
        self.pid, self.peak = pid, 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            self.peak = max(self.peak, _rss_mib(self.pid))
            time.sleep(SAMPLE_PERIOD_S)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, _rss_mib(self.pid))


class _peer:
    """A Zenoh peer connected to `endpoint`, linked before it is handed out."""

    def __init__(self, endpoint: str):
        import zenoh

        config = zenoh.Config()
        config.insert_json5("mode", '"peer"')
        config.insert_json5("connect/endpoints", json.dumps([endpoint]))
        config.insert_json5("listen/endpoints", "[]")
        config.insert_json5("scouting/multicast/enabled", "false")
        self.session = zenoh.open(config)

    def __enter__(self):
        deadline = time.monotonic() + SERVER_START_TIMEOUT_S
        while not list(self.session.info.routers_zid()):
            if time.monotonic() > deadline:
                raise RuntimeError("the peer never linked to the fleet")
            time.sleep(POLL_S)
        return self.session

    def __exit__(self, *exc_info):
        self.session.close()


def _wait_answering(api: str, server: subprocess.Popen) -> None:
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while True:
        if server.poll() is not None:
            raise RuntimeError(f"joshua-fleet exited with {server.returncode}")
        try:
            _robots(api)
            return
        except OSError:
            if time.monotonic() > deadline:
                raise RuntimeError(f"{api} did not answer") from None
            time.sleep(POLL_S)


def _wait_listed(api: str, predicate, observe=None) -> list:
    deadline = time.monotonic() + DRAIN_TIMEOUT_S
    while True:
        robots = _robots(api)
        if observe:
            observe(robots)
        if predicate(robots):
            return robots
        if time.monotonic() > deadline:
            raise RuntimeError(f"{api} never came to the state awaited")
        time.sleep(POLL_S)


def _robots(api: str) -> list:
    with urllib.request.urlopen(api, timeout=10) as response:
        return json.loads(response.read())


def _rss_mib(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024 / MIB
    raise RuntimeError(f"no VmRSS for {pid}")


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]
