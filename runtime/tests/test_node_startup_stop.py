"""A node stopped while it is still starting (importing, opening a device) exits at once, with code 0."""

import signal
import time

import pytest

from testsupport.node_process import start_python

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
    process = start_python(ros_env, SCRIPT)
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
    process = start_python(ros_env, SLOW_IMPORT_SCRIPT)
    try:
        assert process.stdout.readline().strip() == IMPORT_MARKER
        process.send_signal(signum)
        code = process.wait(timeout=STOP_TIMEOUT_S)
    finally:
        process.kill()
    stderr = process.stderr.read()
    assert code == 0, stderr
    assert stderr == ""


RUNTIME_MARKER = "loading the runtime"
# A generated entrypoint run as the supervisor runs it, whose first import of the runtime takes long.
SLOW_RUNTIME_SCRIPT = f"""
import runpy, sys, time

class SlowRuntime:
    def find_spec(self, name, path=None, target=None):
        if name == "joshua_runtime.entrypoint":
            print({RUNTIME_MARKER!r}, flush=True)
            time.sleep({SLOW_START_S})
        return None

sys.meta_path.insert(0, SlowRuntime())
runpy.run_path(sys.argv[1], run_name="__main__")
"""


def test_sigint_while_a_generated_entrypoint_loads_the_runtime_ends_it_with_0_and_no_traceback(tmp_path, ros_env):
    from joshua_codegen.compile import plan_text
    from joshua_codegen.render import render

    description = (
        'robot_config { name: "r" mode: MODE_TELEOPERATION '
        'node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" } }'
    )
    entrypoint = tmp_path / "arm.py"
    entrypoint.write_text(render(plan_text(description))["nodes/arm.py"])
    process = start_python(ros_env, SLOW_RUNTIME_SCRIPT, str(entrypoint))
    try:
        assert process.stdout.readline().strip() == RUNTIME_MARKER
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=STOP_TIMEOUT_S)
    finally:
        process.kill()
    stderr = process.stderr.read()
    assert code == 0, stderr
    assert stderr == ""
