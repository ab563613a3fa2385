"""Preflight: every reason the robot cannot start, found before anything starts."""

import os

from joshua_codegen.supervisor.common import under_script_dir


def preflight(nodes, python):
    """Every reason the robot cannot start, as lines; empty when it can."""
    problems = []
    needs_python = False
    for node in nodes:
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
        binary = node.cpp_binary()
        if binary is not None and os.path.lexists(binary) and not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
            problems.append(f"{node.name}: C++ binary {binary} exists but is not an executable file")
        if spec["kind"] == "custom":
            program = node.custom_program()
            if program is None or not (os.path.isfile(program) and os.access(program, os.X_OK)):
                problems.append(f"{node.name}: program {spec['executable']} is not an executable file (or not on PATH)")
        else:
            needs_python = True
            entrypoint = under_script_dir(spec["entrypoint"])
            if not os.path.isfile(entrypoint):
                problems.append(f"{node.name}: entrypoint {entrypoint} is missing")
    if needs_python and not (os.path.isfile(python) and os.access(python, os.X_OK)):
        problems.append(f"Python interpreter {python} is not an executable file")
    return problems
