"""W501 data-collection-without-recorder: MODE_DATA_COLLECTION with no DATA_SUBSCRIBER node.

What it checks:
    A description in MODE_DATA_COLLECTION declares a DATA_SUBSCRIBER node.

Why it matters:
    Data collection exists to record demonstrations; without a recorder the session is lost
    (unless something outside the description records it).

Example:
    robot_config {
      mode: MODE_DATA_COLLECTION   # warning: MODE_DATA_COLLECTION without a DATA_SUBSCRIBER records nothing
    }
"""

from joshua_codegen.diagnostics import WARNING
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "W501"
NAME = "data-collection-without-recorder"
SEVERITY = WARNING
STAGE = "check"
NEEDS_EVERY_NODE = True


def check(ctx):
    if ctx.config.mode == pb.MODE_DATA_COLLECTION and not any(v.node.type == pb.DATA_SUBSCRIBER for v in ctx.nodes):
        yield Finding(ROBOT + ("mode",), "MODE_DATA_COLLECTION without a DATA_SUBSCRIBER node records nothing")
