"""W103 max-restarts-ignored: max_restarts set on a node that is never restarted.

What it checks:
    A node with `restart: RESTART_NEVER` does not set `max_restarts`.

Why it matters:
    The limit has no effect, which suggests the restart policy is not the one intended.

Example:
    node {
      restart: RESTART_NEVER
      max_restarts: 3            # warning: max_restarts has no effect with RESTART_NEVER
    }
"""

from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "W103"
NAME = "max-restarts-ignored"
SEVERITY = WARNING
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        if view.node.restart == pb.RESTART_NEVER and view.node.HasField("max_restarts"):
            yield Finding(view.at("max_restarts"), "max_restarts has no effect with RESTART_NEVER")
