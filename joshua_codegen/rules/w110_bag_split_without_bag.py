"""W110 bag-split-without-bag: bag_max_size_mb or bag_max_duration_s on a recorder that writes no bag.

What it checks:
    A DATA_SUBSCRIBER sets `bag_max_size_mb` or `bag_max_duration_s` while its output_format is not
    "mcap".

Why it matters:
    Only a ROS bag is split into files; a LeRobot dataset ignores both fields, so the split the
    description asks for never happens.

Example:
    node {
      type: DATA_SUBSCRIBER output_format: "lerobot"
      bag_max_duration_s: 60        # warning: bag_max_duration_s applies to output_format "mcap" only
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding, is_set
from joshua_core.models import BAG_FORMAT
from joshua_core.schema import robot_config_pb2 as pb

CODE = "W110"
NAME = "bag-split-without-bag"
SEVERITY = WARNING
STAGE = "check"
BAG_FIELDS = ("bag_max_size_mb", "bag_max_duration_s")


def check(ctx):
    for view in ctx.typed_nodes:
        if view.node.type != pb.DATA_SUBSCRIBER or defaults.output_format(view.node) == BAG_FORMAT:
            continue
        for field in BAG_FIELDS:
            if is_set(view.node, field):
                yield Finding(
                    view.at(field),
                    f'{field} applies to output_format "{BAG_FORMAT}" only and is ignored '
                    f'(this recorder writes "{defaults.output_format(view.node)}")',
                )
