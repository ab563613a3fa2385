"""E106 missing-executable: a CUSTOM node has no executable.

What it checks:
    Every CUSTOM node sets `executable`: the program it runs (an absolute path or a name on PATH).

Why it matters:
    joshuac starts CUSTOM nodes as given; without a program there is nothing to start.

Example:
    node {
      type: CUSTOM
      name: "planner"            # error: CUSTOM node "planner" has no executable
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E106"
NAME = "missing-executable"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.lacking("executable"):
        yield Finding(view.path, f"{view.label} has no executable")
