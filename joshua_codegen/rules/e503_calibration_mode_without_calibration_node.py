"""E503 calibration-mode-without-calibration-node: MODE_CALIBRATION with no calibration node.

What it checks:
    A description in MODE_CALIBRATION declares an OPERATIONAL_LIMIT_CALIBRATION node.

Why it matters:
    Calibration mode exists to discover joint limits; without that node nothing is calibrated.

Example:
    robot_config {
      mode: MODE_CALIBRATION     # error: MODE_CALIBRATION needs an OPERATIONAL_LIMIT_CALIBRATION node
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E503"
NAME = "calibration-mode-without-calibration-node"
SEVERITY = ERROR
STAGE = "check"
NEEDS_EVERY_NODE = True


def check(ctx):
    if ctx.config.mode == pb.MODE_CALIBRATION and not any(
        v.node.type == pb.OPERATIONAL_LIMIT_CALIBRATION for v in ctx.nodes
    ):
        yield Finding(
            ROBOT + ("mode",), "MODE_CALIBRATION needs an OPERATIONAL_LIMIT_CALIBRATION node; none is declared"
        )
