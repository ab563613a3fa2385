"""The generated supervisors of a robot with hosts, each run inside its simulated computer (testsupport/hosts.py).

    supervisors, logs = start_supervisors(network, out, tmp_path, env)   # out: what `joshuac build` wrote
    wait_for(lambda: all(ready(path.read_text()) for path in logs.values()), timeout_s, supervisors, logs)
    codes = stop_supervisors(supervisors)

Each host's supervisor (out/hosts/<name>/supervisor.py) runs in its host's namespaces with its own control
socket and node logs under `tmp_path`; its output goes to tmp_path/<name>.log.
"""

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

STOP_TIMEOUT_S = 15.0
POLL_S = 0.1


def ready(log: str) -> bool:
    """The supervisor said every node of its host is ready."""
    return re.search(r"^\[ *[\d.]+\] supervisor: ready: (\d+) of \1 nodes ready", log, re.M) is not None


def wait_for(condition, timeout_s: float, supervisors: dict, logs: dict) -> None:
    """Until `condition()` holds; AssertionError with every log when a supervisor ended or time ran out."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        ended = [name for name, supervisor in supervisors.items() if supervisor.poll() is not None]
        assert not ended and time.monotonic() < deadline, {name: path.read_text() for name, path in logs.items()}
        time.sleep(POLL_S)


def start_supervisors(network, out: Path, tmp_path: Path, env: dict) -> tuple[dict, dict]:
    """Every host's supervisor, started in its host: ({name: Popen}, {name: log path})."""
    supervisors, logs = {}, {}
    for host in network:
        logs[host.name] = tmp_path / f"{host.name}.log"
        with open(logs[host.name], "w") as log:
            supervisors[host.name] = host.popen(
                [
                    sys.executable, out / "hosts" / host.name / "supervisor.py",
                    "--control-socket", tmp_path / "control" / f"{host.name}.sock",
                    "--log-dir", tmp_path / "logs" / host.name,
                ],
                env=env, stdout=log, stderr=subprocess.STDOUT,
            )  # fmt: skip
    return supervisors, logs


def stop_supervisors(supervisors: dict) -> dict[str, int | None]:
    """SIGINT to every supervisor at once; each one's exit code (None: still running after STOP_TIMEOUT_S)."""
    for supervisor in supervisors.values():
        supervisor.send_signal(signal.SIGINT)
    codes = {}
    for name, supervisor in supervisors.items():
        try:
            codes[name] = supervisor.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            codes[name] = None  # the hosts' closing kills it
    return codes
