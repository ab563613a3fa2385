"""E116 missing-calibration-file: an OPERATIONAL_LIMIT_CALIBRATION node has no calibration_file.

What it checks:
    Every OPERATIONAL_LIMIT_CALIBRATION node sets `calibration_file`: where the discovered joint
    limits are saved (LeRobot's calibration JSON).

Why it matters:
    Calibration moves every joint through its range by hand; without a file to save to, the
    limits it found are gone when the node stops.

Example:
    node {
      type: OPERATIONAL_LIMIT_CALIBRATION    # error: ... has no calibration_file
      topic_name: "/arm/limits"
      serial_port: "/dev/ttyUSB0"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E116"
NAME = "missing-calibration-file"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.lacking("calibration_file"):
        yield Finding(view.path, f"{view.label} has no calibration_file")
