"""E122 unsupported-policy-type: an INFERENCE node's policy_type is not one the runtime can run.

What it checks:
    `policy_type` of an INFERENCE node, when set, is one of the LeRobot policy types joshua_runtime
    runs (`act`, `diffusion`, `smolvla`; upper or lower case).

Why it matters:
    The node compares it with the type saved in the policy's config.json when it starts, and refuses
    any type it cannot run; without this check the mistake shows only on the robot.

Example:
    node {
      type: INFERENCE
      policy_type: "pi0"     # error: policy_type "pi0" is not supported; supported: act, diffusion, smolvla
    }
"""

import difflib

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.models import POLICY_TYPES
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E122"
NAME = "unsupported-policy-type"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        value = view.node.policy_type
        if view.node.type != pb.INFERENCE or not value or value.lower() in POLICY_TYPES:
            continue
        message = f'policy_type "{value}" is not supported; supported: {", ".join(POLICY_TYPES)}'
        hint = difflib.get_close_matches(value.lower(), POLICY_TYPES, n=1)
        if hint:
            message += f'; did you mean "{hint[0]}"?'
        yield Finding(view.at("policy_type"), message)
