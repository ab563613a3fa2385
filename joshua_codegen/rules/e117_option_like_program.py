"""E117 option-like-program: a program name that env(1) would read as an option or a variable assignment.

What it checks:
    A CUSTOM node's `executable` and the robot's `python_executable` neither begin with `-` nor
    contain `=`.

Why it matters:
    systemd and supervisord run a bare program name (and any program when variables must be passed
    along) through `/usr/bin/env`, which takes a leading `-` for one of its options and `NAME=VALUE`
    for a variable to set: the node would start another program, or none, with other meaning.

Example:
    node {
      type: CUSTOM
      executable: "-i"       # error: executable "-i" begins with "-"; env(1) would read it as an option
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E117"
NAME = "option-like-program"
SEVERITY = ERROR
STAGE = "check"


def _problem(program: str) -> str | None:
    if program.startswith("-"):
        return 'begins with "-"; env(1) would read it as an option'
    if "=" in program:
        return 'contains "="; env(1) would read it as a variable assignment'
    return None


def check(ctx):
    programs = [(ROBOT + ("python_executable",), "python_executable", ctx.config.python_executable)]
    programs += [
        (view.at("executable"), "executable", view.node.executable)
        for view in ctx.typed_nodes
        if view.node.type == pb.CUSTOM
    ]
    for at, field, program in programs:
        problem = _problem(program)
        if problem is not None:
            yield Finding(
                at,
                f'{field} "{program}" {problem}; rename the program or give its absolute path without these characters',
            )
