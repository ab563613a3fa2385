"""E160 lerobot-units-without-calibration: a recorder writes LeRobot units but names no calibration file.

What it checks:
    A DATA_SUBSCRIBER with `units: LEROBOT` or `units: LEROBOT_RANGE` sets `calibration_file`, and
    writes a dataset (output_format `lerobot` or `parquet`, not `mcap`).

Why it matters:
    LeRobot's values are fractions of each joint's calibrated range (the gripper's 0..100, and every
    joint with LEROBOT_RANGE) and follow its drive mode; without the follower's calibration the
    recorder cannot turn joint angles into them. A bag stores messages as they are, in radians.

Example:
    node {
      type: DATA_SUBSCRIBER
      units: LEROBOT                 # error: units LEROBOT needs the follower's calibration_file
      output_directory: "/data/pick"
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.models import BAG_FORMAT
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E160"
NAME = "lerobot-units-without-calibration"
SEVERITY = ERROR
STAGE = "check"
LEROBOT_UNITS = (pb.LEROBOT, pb.LEROBOT_RANGE)


def check(ctx):
    for view in ctx.typed_nodes:
        if view.node.type != pb.DATA_SUBSCRIBER or view.node.units not in LEROBOT_UNITS:
            continue
        units = pb.Units.Name(view.node.units)
        if defaults.output_format(view.node) == BAG_FORMAT:
            yield Finding(
                view.at("units"),
                f'units {units} applies to datasets; output_format "{BAG_FORMAT}" records the messages as they are',
            )
        elif not view.node.calibration_file:
            yield Finding(
                view.at("units"),
                f"units {units} needs the follower's calibration_file (LeRobot's calibration JSON): "
                "LeRobot's values are fractions of each joint's calibrated range",
            )
