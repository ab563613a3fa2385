"""E111 unknown-device: an INFERENCE node's device is not cpu or cuda.

What it checks:
    `device` of an INFERENCE node is empty (default `cpu`), `cpu` or `cuda`.

Why it matters:
    The policy is loaded onto this torch device when the node starts; a wrong name fails only then.

Example:
    node {
      type: INFERENCE
      device: "gpu"              # error: unknown device "gpu"; use cpu or cuda
    }
"""

import difflib

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E111"
NAME = "unknown-device"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        value = view.node.device
        if view.node.type == pb.INFERENCE and value and value not in defaults.DEVICES:
            hint = difflib.get_close_matches(value.lower(), defaults.DEVICES, n=1)
            message = f'unknown device "{value}"'
            message += f'; did you mean "{hint[0]}"?' if hint else f"; use {' or '.join(defaults.DEVICES)}"
            yield Finding(view.at("device"), message)
