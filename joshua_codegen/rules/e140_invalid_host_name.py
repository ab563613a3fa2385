"""E140 invalid-host-name: a `host { }` block without a usable name.

What it checks:
    Each `host { name }` is set and is lower case letters, digits and underscores, starting with a
    letter, at most 32 characters.

Why it matters:
    The name is what nodes and services say they run on (`host: "arm"`), and it names the host's
    output directory (`OUT/hosts/<name>/`), its control socket and `joshuac run --host NAME`.

Example:
    robot_config {
      host { name: "Arm-1" address: "10.0.0.2" }   # error: host name "Arm-1" is not ...
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import HOST_NAME
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E140"
NAME = "invalid-host-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for index, host in enumerate(ctx.config.host):
        if not host.name:
            yield Finding(ROBOT + ("host", index), "the host has no name; write name: with the name nodes use in host:")
        elif not HOST_NAME.fullmatch(host.name):
            yield Finding(
                ROBOT + ("host", index, "name"),
                f'host name "{host.name}" is not lower case letters, digits and underscores starting with a letter '
                "(at most 32 characters)",
            )
