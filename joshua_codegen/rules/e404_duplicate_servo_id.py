"""E404 duplicate-servo-id: a servo id listed twice in one node's device_ids.

What it checks:
    The `device_ids` of a node are distinct. The error is at the repeated id, with the first as a note.

Why it matters:
    Two joints would read and command the same servo; the arm's joint order would be wrong.

Example:
    node {
      device_ids: [1, 2, 3, 3, 5, 6]     # error: servo id 3 is listed twice
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E404"
NAME = "duplicate-servo-id"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        first_at = {}
        for k, servo_id in enumerate(view.node.device_ids):
            first = first_at.setdefault(servo_id, k)
            if first != k:
                yield Finding(
                    view.at("device_ids", k),
                    f"servo id {servo_id} is listed twice in device_ids",
                    ((view.at("device_ids", first), "first listed here"),),
                )
