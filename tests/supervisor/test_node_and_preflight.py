"""Unit tests of the supervisor's node launch decisions and preflight, imported as a package."""

import os
import signal
import sys

import pytest

from joshua_codegen.supervisor.common import exit_text
from joshua_codegen.supervisor.node import Node
from joshua_codegen.supervisor.preflight import PROBE_PREFIX, preflight
from joshua_codegen.supervisor.robot import ROBOT


def spec(**fields) -> dict:
    values = {
        "name": "n",
        "type": "CUSTOM",
        "kind": "custom",
        "entrypoint": "",
        "executable": "true",
        "args": ["-x"],
        "cpp_binary": "",
        "cpp_args": [],
        "restart": "RESTART_NEVER",
        "max_restarts": 0,
        "critical": False,
        "env": {"EXTRA": "1"},
        "fastdds_profile": "fastdds_profile_images.xml",
        "devices": [],
        "model_reference": "",
        "output_directory": "",
    }
    values.update(fields)
    return values


def test_environment_names_the_dds_profile_and_keeps_the_nodes_own_variables():
    env = Node(spec(), sys.executable).environment
    assert env[ROBOT["fastdds_profile_variable"]].endswith("/fastdds_profile_images.xml")
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


@pytest.mark.process
def test_preflight_lists_every_problem(tmp_path):
    nodes = [
        Node(spec(name="a", executable=str(tmp_path / "nothing")), sys.executable),
        Node(
            spec(
                name="b",
                kind="python",
                entrypoint=str(tmp_path / "b.py"),
                devices=[
                    {"kind": "model", "path": str(tmp_path / "model")},
                    {"kind": "serial", "path": str(tmp_path / "tty")},
                ],
            ),
            sys.executable,
        ),
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


def test_preflight_resolves_registry_references_in_the_registry_the_node_sees(tmp_path):
    registry = tmp_path / "registry"
    (registry / "act_arm" / "0123abcd").mkdir(parents=True)
    (registry / "act_arm" / "0123abcd" / ROBOT["model_registry"]["entry_file"]).write_text("{}")
    env = {ROBOT["model_registry"]["variable"]: str(registry)}
    references = [
        "registry:act_arm",
        "registry:act_arm@0123abcd",
        "registry:act_arm@ffff",
        "registry:other",
        "registry:../registry/act_arm",
    ]
    nodes = [
        Node(spec(name=f"n{i}", model_reference=reference, env=env), sys.executable)
        for i, reference in enumerate(references)
    ]
    assert preflight(nodes, sys.executable) == [
        f"n2: registry:act_arm@ffff is not in the model registry at {registry}",
        f"n3: registry:other is not in the model registry at {registry}",
        f"n4: registry:../registry/act_arm is not in the model registry at {registry}",
    ]


def test_preflight_refuses_output_directories_the_node_cannot_write(tmp_path):
    (tmp_path / "a_file").write_text("")
    directories = [str(tmp_path / "new" / "episodes"), str(tmp_path / "a_file" / "episodes"), "/proc/joshua/episodes"]
    nodes = [
        Node(spec(name=f"n{i}", output_directory=directory), sys.executable) for i, directory in enumerate(directories)
    ]
    problems = preflight(nodes, sys.executable)
    assert problems[0] == f"n1: output directory {directories[1]}: {tmp_path / 'a_file'} is not a directory"
    assert problems[1].startswith(f"n2: output directory {directories[2]}: cannot write in /proc: ")
    assert len(problems) == 2
    assert not (tmp_path / "new").exists()
    assert not [path for path in tmp_path.iterdir() if path.name.startswith(PROBE_PREFIX)]


def python_node(tmp_path) -> Node:
    entrypoint = tmp_path / "n.py"
    entrypoint.write_text("")
    return Node(spec(kind="python", entrypoint=str(entrypoint)), sys.executable)


@pytest.mark.process
def test_preflight_accepts_an_interpreter_with_the_runtime_of_this_settings_format(tmp_path):
    assert preflight([python_node(tmp_path)], sys.executable) == []


@pytest.mark.process
def test_preflight_names_the_install_command_when_the_interpreter_lacks_the_runtime(tmp_path):
    base = sys._base_executable  # the interpreter this environment was made from: no joshua_runtime
    assert base != sys.executable
    [problem] = preflight([python_node(tmp_path)], base)
    assert problem.startswith(f"{base} cannot import the runtime (ModuleNotFoundError: No module named ")
    assert "joshuac build CONFIG -o OUT --bundle" in problem and "install.sh" in problem


@pytest.mark.process
def test_preflight_refuses_a_runtime_of_another_settings_format(tmp_path):
    old_runtime = tmp_path / "python"
    old_runtime.write_text("#!/bin/sh\necho 1\n")
    old_runtime.chmod(0o755)
    [problem] = preflight([python_node(tmp_path)], str(old_runtime))
    assert problem.startswith(
        f"the runtime installed for {old_runtime} reads node settings format 1, "
        f"this build writes format {ROBOT['settings_format_version']}; "
    )


def test_readiness_counts_only_the_main_process_and_warns_about_a_node_that_never_gets_ready(capsys, tmp_path):
    import socket

    from joshua_codegen.supervisor.notify import Readiness

    node = python_node(tmp_path)
    readiness = Readiness([node], "unit")
    try:
        assert node.environment["NOTIFY_SOCKET"] == readiness.address and readiness.address.startswith("@")
        node.state, node.started_at = "running", 0.0
        readiness.on_launch(node, 0.0)
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sender:
            sender.sendto(b"READY=1\nSTATUS=serving", "\0" + readiness.address[1:])
            readiness.receive(lambda pid: None, 1.0)  # this process is no node's main process
            assert not node.ready
            readiness.on_timer(readiness.next_deadline(), stopping=False)
            assert "warning: not ready 60 s after its start" in capsys.readouterr().err
            sender.sendto(b"READY=1\nSTATUS=serving", "\0" + readiness.address[1:])
            readiness.receive(lambda pid: node if pid == os.getpid() else None, 2.0)
        assert node.ready and node.status_text == "serving"
        readiness.on_timer(2.0, stopping=False)
        assert "supervisor: ready: 1 of 1 nodes ready" in capsys.readouterr().err
    finally:
        readiness.socket.close()
