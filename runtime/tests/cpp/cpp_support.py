"""Helpers of the C++ node tests: the binaries in build/bin and the command line the supervisor gives them.

The command of a node comes from the real compiler (the `cpp_args` of its planned process), so these
tests run each binary exactly as the generated supervisor execs it.
"""

import subprocess
from collections.abc import Sequence
from pathlib import Path

import pytest

from joshua_codegen.compile import DescriptionError
from joshua_codegen.compile import cpp_commands as compiled_cpp_commands
from testsupport.node_process import NodeProcess

ROOT = Path(__file__).resolve().parents[3]
BIN_DIR = ROOT / "build" / "bin"
NODE_START_TIMEOUT_S = 30.0  # the Python twin is a cold rclpy process on a busy 2-core machine
MESSAGE_TIMEOUT_S = 15.0
STOP_BOUND_S = 2.0  # generous; the contract (0.5 s) is measured by bench/cpp_nodes.py


def cpp_commands(description_text: str, overrides: Sequence[str] = (),
                 path: str = "test_description.pbtxt") -> dict[str, list[str]]:
    """argv of every node that has a C++ binary, by node name: `BIN_DIR/<binary> --ros-args ...`."""
    try:
        return compiled_cpp_commands(description_text, str(BIN_DIR), overrides, path)
    except DescriptionError as exc:
        pytest.fail(f"the test description does not compile:\n{exc}", pytrace=False)


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
