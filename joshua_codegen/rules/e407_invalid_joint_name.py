"""E407 invalid-joint-name: an empty or repeated joint name in one node.

What it checks:
    Every `joint_names` entry is non-empty and appears once in its node.

Why it matters:
    JointState messages and recorded datasets key positions by joint name; an empty or repeated
    name makes two joints indistinguishable.

Example:
    node {
      joint_names: ["pan", "lift", "lift", "flex", "roll", "grip"]   # error: joint name "lift" is listed twice
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E407"
NAME = "invalid-joint-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        first_at = {}
        for k, name in enumerate(view.node.joint_names):
            if not name:
                yield Finding(view.at("joint_names", k), "joint name is empty")
                continue
            first = first_at.setdefault(name, k)
            if first != k:
                yield Finding(
                    view.at("joint_names", k),
                    f'joint name "{name}" is listed twice',
                    ((view.at("joint_names", first), "first listed here"),),
                )
