"""A node stopped while it is still starting (importing, opening a device) exits at once, with code 0."""

import signal
import subprocess
import sys
import time

import pytest

STARTUP_MARKER = "starting slowly"
STOP_TIMEOUT_S = 5.0
SLOW_START_S = 60.0

SCRIPT = f"""
import sys, time
from joshua_core.settings import FORMAT_VERSION
from joshua_runtime import entrypoint
from joshua_runtime.node import JoshuaNode

class SlowStart(JoshuaNode):
    closed = False
    def start(self):
        print({STARTUP_MARKER!r}, flush=True)
        time.sleep({SLOW_START_S})
    def close(self):
        print("closed", flush=True)

entrypoint.node_class = lambda node_type: SlowStart
entrypoint.run_node({{"format_version": FORMAT_VERSION, "name": "slow", "type": "CUSTOM"}})
"""


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signal_during_start_ends_the_node_cleanly(signum, ros_env):
    process = subprocess.Popen(
        [sys.executable, "-c", SCRIPT], env=ros_env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout.readline().strip() == STARTUP_MARKER
        sent = time.monotonic()
        process.send_signal(signum)
        code = process.wait(timeout=STOP_TIMEOUT_S)
        elapsed = time.monotonic() - sent
    finally:
        process.kill()
    assert code == 0, process.stderr.read()
    assert process.stdout.read().strip() == "closed"
    assert elapsed < SLOW_START_S


IMPORT_MARKER = "importing rclpy"
# A node process whose import of rclpy takes long (a cold disk, a busy machine), made to by a finder
# that waits when rclpy is looked up.
SLOW_IMPORT_SCRIPT = f"""
import sys, time
from joshua_core.settings import FORMAT_VERSION
from joshua_runtime import entrypoint

class SlowRclpy:
    def find_spec(self, name, path=None, target=None):
        if name == "rclpy":
            print({IMPORT_MARKER!r}, flush=True)
            time.sleep({SLOW_START_S})
        return None

sys.meta_path.insert(0, SlowRclpy())
entrypoint.run_node({{"format_version": FORMAT_VERSION, "name": "slow", "type": "MOCK_ENCODER_PUBLISHER"}})
"""


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signal_while_the_runtime_imports_rclpy_ends_the_node_with_0_and_no_traceback(signum, ros_env):
    process = subprocess.Popen(
        [sys.executable, "-c", SLOW_IMPORT_SCRIPT],
        env=ros_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert process.stdout.readline().strip() == IMPORT_MARKER
        process.send_signal(signum)
        code = process.wait(timeout=STOP_TIMEOUT_S)
    finally:
        process.kill()
    stderr = process.stderr.read()
    assert code == 0, stderr
    assert stderr == ""
