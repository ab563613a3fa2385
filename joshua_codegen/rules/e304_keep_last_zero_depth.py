"""E304 keep-last-zero-depth: KEEP_LAST history with a depth of 0.

What it checks:
    A node (or a topic a CUSTOM node declares) with KEEP_LAST history (the default) does not set `qos_depth: 0`.

Why it matters:
    A KEEP_LAST queue of depth 0 holds no message (rmw replaces it with a default or refuses it).

Example:
    node {
      qos_depth: 0               # error: qos_depth 0 with KEEP_LAST history keeps no message
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E304"
NAME = "keep-last-zero-depth"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for _view, holder, path in ctx.topic_holders:
        if holder.qos_history != pb.KEEP_ALL and holder.HasField("qos_depth") and holder.qos_depth == 0:
            yield Finding(
                path + ("qos_depth",), "qos_depth 0 with KEEP_LAST history keeps no message; use a depth of 1 or more"
            )
