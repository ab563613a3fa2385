"""E501 inference-mode-without-policy: MODE_INFERENCE with no INFERENCE node.

What it checks:
    A description in MODE_INFERENCE declares at least one INFERENCE node.

Why it matters:
    In inference mode a policy drives the robot; without one nothing commands the actuators.

Example:
    robot_config {
      mode: MODE_INFERENCE       # error: MODE_INFERENCE needs an INFERENCE node; none is declared
      node { type: ACTUATOR_SUBSCRIBER ... }
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E501"
NAME = "inference-mode-without-policy"
SEVERITY = ERROR
STAGE = "check"
NEEDS_EVERY_NODE = True


def check(ctx):
    if ctx.config.mode == pb.MODE_INFERENCE and not any(v.node.type == pb.INFERENCE for v in ctx.nodes):
        yield Finding(ROBOT + ("mode",), "MODE_INFERENCE needs an INFERENCE node; none is declared")
