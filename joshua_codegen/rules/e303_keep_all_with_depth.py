"""E303 keep-all-with-depth: qos_depth set together with qos_history KEEP_ALL.

What it checks:
    A node (or a topic a CUSTOM node declares) with `qos_history: KEEP_ALL` leaves `qos_depth` unset.

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
    for _view, holder, path in ctx.topic_holders:
        if holder.qos_history == pb.KEEP_ALL and holder.HasField("qos_depth"):
            yield Finding(
                path + ("qos_depth",),
                "qos_depth is ignored with KEEP_ALL history; remove it, or use qos_history: KEEP_LAST",
            )
