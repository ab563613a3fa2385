"""E102 mode-unspecified: the robot has no mode.

What it checks:
    `robot_config.mode` is set to one of MODE_TELEOPERATION, MODE_SIMULATION, MODE_INFERENCE,
    MODE_DATA_COLLECTION or MODE_CALIBRATION.

Why it matters:
    The mode decides which processes run (hardware or simulation, policy, recorder); there is no
    safe default.

Example:
    robot_config {
      name: "arm"            # error: mode is not set
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import RobotConfig

CODE = "E102"
NAME = "mode-unspecified"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    if ctx.config.mode == 0:
        modes = [v.name for v in RobotConfig.DESCRIPTOR.fields_by_name["mode"].enum_type.values if v.number]
        yield Finding(ROBOT + ("mode",), f"mode is not set; choose one of {', '.join(modes)}")
