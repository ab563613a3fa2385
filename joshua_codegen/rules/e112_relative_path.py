"""E112 relative-path: a program or directory path that depends on the current directory.

What it checks:
    A CUSTOM node's `executable`, and the robot's `python_executable`, are either absolute
    (`/usr/bin/tool`) or a bare name looked up on PATH (`tool`), never a relative path with a
    slash (`bin/tool`, `./tool`). `cpp_bin_dir` is absolute.

Why it matters:
    Nodes are started by systemd, supervisord or the supervisor, each from its own working
    directory; a relative path would find a different file, or none, depending on who starts it.

Example:
    node {
      type: CUSTOM
      executable: "scripts/planner.py"   # error: executable "scripts/planner.py" is a relative path
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E112"
NAME = "relative-path"
SEVERITY = ERROR
STAGE = "check"
ADVICE = "use an absolute path, or a bare program name found on PATH"


def _relative_program(path: str) -> bool:
    return "/" in path and not path.startswith("/")


def check(ctx):
    config = ctx.config
    if _relative_program(config.python_executable):
        yield Finding(
            ROBOT + ("python_executable",),
            f'python_executable "{config.python_executable}" is a relative path; {ADVICE}',
        )
    if config.cpp_bin_dir and not config.cpp_bin_dir.startswith("/"):
        yield Finding(
            ROBOT + ("cpp_bin_dir",),
            f'cpp_bin_dir "{config.cpp_bin_dir}" is a relative path; use an absolute directory',
        )
    for view in ctx.typed_nodes:
        if view.node.type == pb.CUSTOM and _relative_program(view.node.executable):
            yield Finding(view.at("executable"), f'executable "{view.node.executable}" is a relative path; {ADVICE}')
