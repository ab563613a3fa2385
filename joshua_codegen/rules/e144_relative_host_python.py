"""E144 relative-host-python: a host's `python` is not an absolute path.

What it checks:
    `host { python }`, when set, is an absolute, printable path such as "/usr/bin/python3".

Why it matters:
    install.sh on that computer makes the host's virtual environment with this interpreter; with
    `ros_from_system` it must be the one apt's ROS packages were built for, found without depending
    on the PATH of whoever runs the script.

Example:
    robot_config {
      host { name: "pi" address: "10.0.0.3" ros_from_system: true python: "python3" }   # error
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E144"
NAME = "relative-host-python"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for index, host in enumerate(ctx.config.host):
        python = host.python
        if python and not (python.startswith("/") and python.isprintable() and " " not in python):
            yield Finding(
                ROBOT + ("host", index, "python"),
                f'python "{python}" is not an absolute path (e.g. "/usr/bin/python3")',
            )
