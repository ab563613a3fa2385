"""Helpers of the C++ node tests: the binaries in build/bin and the command line the supervisor gives them.

The command of a node comes from the real compiler (the `cpp_args` of its planned process), so these
tests run each binary exactly as the generated supervisor execs it.
"""

import subprocess
from collections.abc import Sequence
from pathlib import Path

import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from joshua_codegen.compile import DescriptionError
from joshua_codegen.compile import cpp_commands as compiled_cpp_commands
from joshua_core import so100
from testsupport.compiled_settings import compiled_settings
from testsupport.node_process import NodeProcess

ROOT = Path(__file__).resolve().parents[3]
BIN_DIR = ROOT / "build" / "bin"
NODE_START_TIMEOUT_S = 30.0  # the Python twin is a cold rclpy process on a busy 2-core machine
MESSAGE_TIMEOUT_S = 15.0
STOP_BOUND_S = 2.0  # generous; the contract (0.5 s) is measured by bench/cpp_nodes.py
JOINTS = list(so100.SO100_JOINTS)
IDS = [1, 2, 3, 4, 5, 6]
POSES = ([1200, 1800, 2600, 3000, 900, 2300], [2900, 2200, 1500, 1100, 3600, 1700])
# Offsets, a reversed joint and narrow ranges, so a difference in applying the file shows.
CALIBRATION = {
    name: {"id": servo_id, "drive_mode": 1 if name == "elbow_flex" else 0, "homing_offset": 10 * servo_id - 30,
           "range_min": 600 + 10 * servo_id, "range_max": 3400 - 20 * servo_id}
    for servo_id, name in zip(IDS, JOINTS)
}
TWINS = """
robot_config {{
  name: "parity"
  mode: MODE_TELEOPERATION
  node {{ name: "py_{kind}" type: {type} preferred_backend: PYTHON {fields} topic_name: "/py/{topic}" }}
  node {{ name: "cpp_{kind}" type: {type} preferred_backend: CPP {fields} topic_name: "/cpp/{topic}" }}
}}
"""
READER_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)


def cpp_commands(description_text: str, overrides: Sequence[str] = (),
                 path: str = "test_description.pbtxt") -> dict[str, list[str]]:
    """argv of every node that has a C++ binary, by node name: `BIN_DIR/<binary> --ros-args ...`."""
    try:
        return compiled_cpp_commands(description_text, str(BIN_DIR), overrides, path)
    except DescriptionError as exc:
        pytest.fail(f"the test description does not compile:\n{exc}", pytrace=False)


def twins(kind: str, node_type: str, topic: str, fields: str, overrides: list[str]):
    """(Python settings, C++ argv) of the twin nodes `py_<kind>` and `cpp_<kind>`."""
    text = TWINS.format(kind=kind, type=node_type, topic=topic, fields=fields)
    return compiled_settings(text, overrides)[f"py_{kind}"], cpp_commands(text, overrides)[f"cpp_{kind}"]


class CppNodeProcess(NodeProcess):
    """A C++ node binary run with `argv` and `env`; otherwise testsupport's NodeProcess."""

    def __init__(self, argv: list[str], env: dict):
        self.process = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def wait(self, timeout: float = NODE_START_TIMEOUT_S) -> tuple[int, str]:
        return super().wait(timeout)


def error_line(stderr: str) -> str:
    """The message of the node's one-line error `NAME: error: MESSAGE` (the last line of stderr)."""
    lines = stderr.strip().splitlines()
    assert lines and ": error: " in lines[-1], stderr
    return lines[-1].split(": error: ", 1)[1]
