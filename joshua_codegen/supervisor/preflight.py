"""Preflight: every reason the robot cannot start, found before anything starts."""

import os

from joshua_codegen.supervisor.common import executable_file, under_script_dir
from joshua_codegen.supervisor.policy import RUNTIME_PROBE_TIMEOUT_S
from joshua_codegen.supervisor.robot import ROBOT

PROBE_PREFIX = ".joshua-preflight-"  # a file created and removed at once, to learn a directory is writable
RUNTIME_PROBE = "import joshua_runtime, joshua_core.settings as s; print(s.FORMAT_VERSION)"
INSTALL_SCRIPT = "install.sh"  # written next to supervisor.py by `joshuac build --bundle`


def runtime_fix(python: str) -> str:
    """How to install the runtime this build needs for `python`."""
    script = under_script_dir(INSTALL_SCRIPT)
    if os.path.isfile(script):
        return f"install it: sh {script} (then run supervisor.py with that environment's python)"
    return (
        f"build with `joshuac build CONFIG -o OUT --bundle` and run `sh OUT/{INSTALL_SCRIPT}` on the robot, "
        f"or install this repository's core/ and runtime/ for {python}"
    )


def runtime_problem(python: str, env: dict[str, str]) -> str | None:
    """Why `python` cannot run this build's Python nodes (no joshua_runtime, or another settings format), or None."""
    import subprocess

    expected = ROBOT["settings_format_version"]
    try:
        probe = subprocess.run(
            [python, "-c", RUNTIME_PROBE],
            env=env,
            capture_output=True,
            text=True,
            timeout=RUNTIME_PROBE_TIMEOUT_S,
            stdin=subprocess.DEVNULL,
        )
    except subprocess.TimeoutExpired:
        return f"{python} did not report its joshua_runtime within {RUNTIME_PROBE_TIMEOUT_S:g} s"
    except OSError as exc:
        return f"cannot run {python}: {exc.strerror or exc}"
    lines = probe.stdout.split()
    if probe.returncode != 0 or not lines or not lines[-1].isdigit():
        reason = (probe.stderr.strip().splitlines() or [f"exit code {probe.returncode}"])[-1]
        return f"{python} cannot import the runtime ({reason}); {runtime_fix(python)}"
    if int(lines[-1]) != expected:
        return (
            f"the runtime installed for {python} reads node settings format {lines[-1]}, this build writes "
            f"format {expected}; {runtime_fix(python)}"
        )
    return None


def registry_problem(reference: str, env: dict[str, str]) -> str | None:
    """Why `registry:NAME[@REVISION]` names no entry of the model registry the node will see, or None."""
    registry = ROBOT["model_registry"]
    root = os.path.expanduser(env.get(registry["variable"]) or registry["default_root"])
    name, _, revision = reference[len(registry["prefix"]) :].partition("@")
    if name and "/" not in name + revision and name not in (".", "..") and revision not in (".", ".."):
        try:
            revisions = [revision] if revision else os.listdir(os.path.join(root, name))
        except OSError:
            revisions = []
        if any(os.path.isfile(os.path.join(root, name, each, registry["entry_file"])) for each in revisions):
            return None
    return f"{reference} is not in the model registry at {root}"


def output_problem(directory: str) -> str | None:
    """Why the node cannot write into `directory` (created by the node when missing), or None."""
    path = os.path.abspath(os.path.expanduser(directory))
    existing = path
    while not os.path.lexists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        return f"output directory {directory}: {existing} is not a directory"
    probe_path = os.path.join(existing, f"{PROBE_PREFIX}{os.getpid()}")
    try:
        os.close(os.open(probe_path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        os.unlink(probe_path)
    except OSError as exc:
        return f"output directory {directory}: cannot write in {existing}: {exc.strerror or exc}"
    return None


def node_problems(node) -> list[str]:
    """Every reason one node cannot start (its devices, model, output directory, program or entrypoint)."""
    problems = []
    spec = node.spec
    for device in spec["devices"]:
        path, kind = device["path"], device["kind"]
        if kind == "model" and not os.path.isdir(path):
            problems.append(f"{node.name}: model directory {path} does not exist")
        elif kind == "file" and not os.path.isfile(path):
            problems.append(f"{node.name}: video file {path} does not exist")
        elif kind in ("serial", "camera") and not os.path.exists(path):
            what = "serial port" if kind == "serial" else "camera device"
            problems.append(f"{node.name}: {what} {path} does not exist")
    if spec["model_reference"]:
        problem = registry_problem(spec["model_reference"], node.environment)
        if problem:
            problems.append(f"{node.name}: {problem}")
    if spec["output_directory"]:
        problem = output_problem(spec["output_directory"])
        if problem:
            problems.append(f"{node.name}: {problem}")
    binary = node.cpp_binary()
    if binary is not None and os.path.lexists(binary) and not executable_file(binary):
        problems.append(f"{node.name}: C++ binary {binary} exists but is not an executable file")
    if spec["kind"] == "custom":
        program = node.custom_program()
        if program is None or not executable_file(program):
            problems.append(f"{node.name}: program {spec['executable']} is not an executable file (or not on PATH)")
    elif not os.path.isfile(node.entrypoint()):
        problems.append(f"{node.name}: entrypoint {node.entrypoint()} is missing")
    return problems


def preflight(nodes, python):
    """Every reason the robot cannot start, as lines; empty when it can."""
    problems = [problem for node in nodes for problem in node_problems(node)]
    needs_python = any(node.spec["kind"] != "custom" for node in nodes)
    if needs_python and not executable_file(python):
        problems.append(f"Python interpreter {python} is not an executable file")
    elif needs_python:
        environment = next(node.environment for node in nodes if node.spec["kind"] != "custom")
        problem = runtime_problem(python, environment)
        if problem:
            problems.append(problem)
    return problems
