"""E131 foxglove-name-taken: a node is named like the Foxglove bridge process.

What it checks:
    With `foxglove { }` set, no node is named "foxglove_bridge" (written or derived): the build
    adds a process of that name.

Why it matters:
    The name is also the process's entrypoint file and unit: one would overwrite the other.

Example:
    robot_config {
      foxglove { port: 8765 }
      node { name: "foxglove_bridge" type: CUSTOM executable: "/bin/viewer" }   # error: reserved
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E131"
NAME = "foxglove-name-taken"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    if not ctx.config.HasField("foxglove"):
        return
    for view in ctx.nodes:
        if view.name == defaults.FOXGLOVE_NAME:
            yield Finding(
                view.at("name"),
                f'node name "{view.name}" is reserved for the Foxglove bridge process that `foxglove {{ }}` adds',
            )
