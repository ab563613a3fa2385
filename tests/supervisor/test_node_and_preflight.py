"""Unit tests of the supervisor's node launch decisions and preflight, imported as a package."""

import os
import signal
import sys

from joshua_codegen.supervisor.common import exit_text
from joshua_codegen.supervisor.node import Node
from joshua_codegen.supervisor.preflight import preflight
from joshua_codegen.supervisor.robot import ROBOT


def spec(**fields) -> dict:
    values = {"name": "n", "type": "CUSTOM", "kind": "custom", "entrypoint": "", "executable": "true", "args": ["-x"],
              "cpp_binary": "", "cpp_args": [], "restart": "RESTART_NEVER", "max_restarts": 0, "critical": False,
              "env": {"EXTRA": "1"}, "devices": []}
    values.update(fields)
    return values


def test_environment_names_the_dds_profile_and_keeps_the_nodes_own_variables():
    env = Node(spec(), sys.executable).environment
    assert env[ROBOT["fastdds_profile_variable"]].endswith(ROBOT["fastdds_profile"])
    assert env["PYTHONUNBUFFERED"] == "1" and env["EXTRA"] == "1"


def test_a_missing_cpp_binary_falls_back_to_python_with_one_warning(capsys, tmp_path):
    node = Node(spec(kind="python", entrypoint="nodes/n.py", cpp_binary="not_there"), sys.executable)
    first, backend = node.command()
    assert backend == "Python" and first[0] == sys.executable and first[1].endswith("nodes/n.py")
    node.command()
    assert capsys.readouterr().err.count("C++ binary") == 1


def test_a_custom_program_is_found_on_path():
    argv, backend = Node(spec(), sys.executable).command()
    assert backend == "custom" and os.path.basename(argv[0]) == "true" and argv[1:] == ["-x"]


def test_preflight_lists_every_problem(tmp_path):
    nodes = [
        Node(spec(name="a", executable=str(tmp_path / "nothing")), sys.executable),
        Node(spec(name="b", kind="python", entrypoint=str(tmp_path / "b.py"),
                  devices=[{"kind": "model", "path": str(tmp_path / "model")},
                           {"kind": "serial", "path": str(tmp_path / "tty")}]), sys.executable),
    ]
    problems = preflight(nodes, sys.executable)
    assert problems == [
        f"a: program {tmp_path / 'nothing'} is not an executable file (or not on PATH)",
        f"b: model directory {tmp_path / 'model'} does not exist",
        f"b: serial port {tmp_path / 'tty'} does not exist",
        f"b: entrypoint {tmp_path / 'b.py'} is missing",
    ]


def test_exit_text_names_the_signal_or_the_code():
    assert exit_text(signal.SIGKILL) == "killed by SIGKILL"
    assert exit_text(3 << 8) == "exited with code 3"
