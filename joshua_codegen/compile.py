"""The whole compiler as one pure function: description text in, diagnostics and files out."""

import os
from dataclasses import dataclass

from joshua_core.settings import to_literal

from joshua_codegen.check import CheckResult, check_file, check_text
from joshua_codegen.diagnostics import format_text
from joshua_codegen.model import Robot
from joshua_codegen.plan import plan
from joshua_codegen.render import render


@dataclass
class Compilation:
    check: CheckResult
    files: dict[str, str] | None  # None when the description has errors
    robot: Robot | None = None  # the planned model, when files were rendered

    @property
    def robot_name(self) -> str | None:
        description = self.check.description
        return description.robot_config.name if description is not None else None


def compile_file(path: str, overrides=(), prefix: str | None = None) -> Compilation:
    """Check a description and, when it has no error, render every output file."""
    result = check_file(path, overrides, prefix)
    if result.has_errors or result.description is None:
        return Compilation(result, None)
    robot = result.robot or plan(result.description, path)
    return Compilation(result, render(robot, prefix), robot)


class DescriptionError(Exception):
    """A description given as text has errors; the message holds joshuac's diagnostics."""


def plan_text(text: str, overrides=(), path: str = "description.pbtxt") -> Robot:
    """The model of a description given as text. Raises DescriptionError when it has errors."""
    result = check_text(path, text, overrides)
    if result.has_errors or result.description is None:
        raise DescriptionError(format_text(result.diagnostics, result.sources))
    return result.robot or plan(result.description, path)


def cpp_commands(text: str, bin_dir: str, overrides=(), path: str = "description.pbtxt") -> dict[str, list[str]]:
    """The argv the supervisor execs for each node with a C++ binary (`BIN_DIR/<binary> --ros-args ...`), by name.

    Raises DescriptionError when the description has errors.
    """
    robot = plan_text(text, overrides, path)
    return {p.name: [os.path.join(bin_dir, p.cpp_binary), *p.cpp_args] for p in robot.processes if p.cpp_binary}


def node_settings(text: str, overrides=(), path: str = "description.pbtxt") -> dict[str, dict]:
    """What the generated entrypoints would pass to run_node, by process name, for a description text.

    For tools and tests that start nodes without writing a build. Includes the simulation engine's
    settings in MODE_SIMULATION. Raises DescriptionError when the description has errors.
    """
    robot = plan_text(text, overrides, path)
    settings = {node.name: node.settings for node in robot.nodes}
    for process in robot.processes:
        settings[process.name] = robot.process_settings(process)
    return {name: to_literal(value) for name, value in settings.items()}
