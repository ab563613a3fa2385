"""E110 unknown-output-format: a DATA_SUBSCRIBER's output_format is not lerobot, parquet or mcap.

What it checks:
    `output_format` of a DATA_SUBSCRIBER is empty (default `lerobot`), `lerobot` (LeRobotDataset
    v3.0 with video), `parquet` (tables only, no video) or `mcap` (a rosbag2 MCAP bag).

Why it matters:
    The recorder writes only these formats; anything else would fail when recording starts.

Example:
    node {
      type: DATA_SUBSCRIBER
      output_format: "LeRobot"   # error: unknown output_format "LeRobot"; did you mean "lerobot"?
    }
"""

import difflib

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E110"
NAME = "unknown-output-format"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        value = view.node.output_format
        if view.node.type == pb.DATA_SUBSCRIBER and value and value not in defaults.OUTPUT_FORMATS:
            hint = difflib.get_close_matches(value.lower(), defaults.OUTPUT_FORMATS, n=1)
            message = f'unknown output_format "{value}"'
            message += f'; did you mean "{hint[0]}"?' if hint else f"; use {' or '.join(defaults.OUTPUT_FORMATS)}"
            yield Finding(view.at("output_format"), message)
