"""A process whose ROS teardown hangs in native code holding the GIL still ends, with the code it meant to end with.

Fast DDS 2.14 can deadlock while a process deletes its participant (exit_timer.py); the tests make the
same kind of hang with a C library call made through ctypes.PyDLL, which keeps the GIL while it waits.
"""

import signal
import subprocess
import sys
import time
from pathlib import Path

from testsupport.compiled_settings import compiled_node
from testsupport.node_process import start_python

HANG_S = 60  # far past any deadline and every wait of these tests
EXIT_WAIT_S = 30.0  # a cold Python process on a busy 2-core machine
POLL_S = 0.05

BLOCK = f"""
import ctypes, sys, time
from joshua_runtime.exit_timer import exit_after
with exit_after(0.3, 7):
    print("in the block", flush=True)
    if sys.argv[1] == "hang":
        ctypes.PyDLL(None).sleep({HANG_S})
time.sleep(0.6)
print("after the block", flush=True)
sys.exit(5)
"""


def run_block(mode: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", BLOCK, mode], capture_output=True, text=True, timeout=HANG_S / 2, check=False
    )


def test_a_block_that_hangs_holding_the_gil_ends_the_process_with_the_given_code():
    finished = run_block("hang")
    assert (finished.returncode, finished.stdout) == (7, "in the block\n"), finished.stderr


def test_a_block_that_finishes_in_time_leaves_the_process_running():
    finished = run_block("return")
    assert (finished.returncode, finished.stdout) == (5, "in the block\nafter the block\n"), finished.stderr


HANGING_TEARDOWN = f"""
import ctypes, sys
import rclpy.node
from joshua_runtime.entrypoint import run_node

def destroy_node(self):
    print("destroying the node", file=sys.stderr, flush=True)
    ctypes.PyDLL(None).sleep({HANG_S})

rclpy.node.Node.destroy_node = destroy_node
run_node(SETTINGS)
"""


def test_a_node_whose_dds_teardown_hangs_stops_with_code_0(ros_env, tmp_path):
    settings = compiled_node('name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states"')
    log_path = tmp_path / "stderr.txt"
    with open(log_path, "w") as log:
        process = start_python(ros_env, HANGING_TEARDOWN.replace("SETTINGS", repr(settings)), stderr=log)
    try:
        _wait_for_line(log_path, "ready: ", process)
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=EXIT_WAIT_S)
    finally:
        process.kill()
        process.wait()
    log = log_path.read_text()
    assert "destroying the node" in log
    assert code == 0, log


def _wait_for_line(path: Path, text: str, process: subprocess.Popen) -> None:
    deadline = time.monotonic() + EXIT_WAIT_S
    while text not in path.read_text():
        assert process.poll() is None, f"the node ended with {process.returncode}:\n{path.read_text()}"
        assert time.monotonic() < deadline, f"no {text!r} within {EXIT_WAIT_S} s:\n{path.read_text()}"
        time.sleep(POLL_S)
