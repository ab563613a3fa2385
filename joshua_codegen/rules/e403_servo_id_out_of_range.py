"""E403 servo-id-out-of-range: a servo id above 253.

What it checks:
    Every `device_ids` entry is between 0 and 253.

Why it matters:
    The STS3215 protocol has ids 0-253 only; 254 is the broadcast id (every servo obeys, none
    answers) and 255 is not an id at all.

Example:
    node {
      device_ids: [1, 2, 254]    # error: servo id 254 is out of range 0-253 (254 is the broadcast id)
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E403"
NAME = "servo-id-out-of-range"
SEVERITY = ERROR
STAGE = "check"
MAX_SERVO_ID = 253
BROADCAST_ID = 254


def check(ctx):
    for view in ctx.nodes:
        for k, servo_id in enumerate(view.node.device_ids):
            if servo_id > MAX_SERVO_ID:
                note = " (254 is the broadcast id)" if servo_id == BROADCAST_ID else ""
                yield Finding(view.at("device_ids", k), f"servo id {servo_id} is out of range 0-{MAX_SERVO_ID}{note}")
