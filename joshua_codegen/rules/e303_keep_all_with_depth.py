"""E303 keep-all-with-depth: qos_depth set together with qos_history KEEP_ALL.

What it checks:
    A node with `qos_history: KEEP_ALL` leaves `qos_depth` unset.

Why it matters:
    KEEP_ALL ignores the depth; writing one suggests KEEP_LAST was meant, and the memory use
    differs greatly between the two.

Example:
    node {
      qos_history: KEEP_ALL
      qos_depth: 10              # error: qos_depth is ignored with KEEP_ALL
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E303"
NAME = "keep-all-with-depth"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        if view.node.qos_history == pb.KEEP_ALL and view.node.HasField("qos_depth"):
            yield Finding(view.at("qos_depth"), "qos_depth is ignored with KEEP_ALL history; "
                                                "remove it, or use qos_history: KEEP_LAST")
