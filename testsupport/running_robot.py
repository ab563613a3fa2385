"""A robot built by joshuac and run by its generated supervisor, for tests that meet it as its users do."""

import contextlib
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

from testsupport.joshuac_cli import joshuac

READY_TIMEOUT_S = 60.0  # every node of a small mock robot ready, on a loaded machine
STOP_TIMEOUT_S = 15.0
POLL_S = 0.1


@contextlib.contextmanager
def running_robot(description: str, directory: Path, env: dict):
    """Build `description` into directory/out, run its supervisor until every node is ready, yield OUT;
    stop it with SIGINT afterwards and fail when it does not end cleanly."""
    source = directory / "robot.pbtxt"
    source.write_text(description)
    out = directory / "out"
    built = joshuac("build", source, "-o", out)
    assert built.returncode == 0, built.stderr
    log_path = directory / "supervisor.log"
    with open(log_path, "w") as log:
        supervisor = subprocess.Popen(
            [sys.executable, str(out / "supervisor.py")], stdout=log, stderr=subprocess.STDOUT, env=env
        )
    try:
        _wait_ready(supervisor, log_path)
        yield out
    finally:
        supervisor.send_signal(signal.SIGINT)
        try:
            code = supervisor.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            supervisor.wait()
            code = None
    assert code == 0, f"the supervisor ended with {code}:\n{log_path.read_text()}"


def _wait_ready(supervisor: subprocess.Popen, log_path: Path) -> None:
    deadline = time.monotonic() + READY_TIMEOUT_S
    while not re.search(r"^\[ *[\d.]+\] supervisor: ready: (\d+) of \1 nodes ready", log_path.read_text(), re.M):
        if supervisor.poll() is not None or time.monotonic() > deadline:
            raise AssertionError(f"the robot did not get ready:\n{log_path.read_text()}")
        time.sleep(POLL_S)
