"""E107 missing-model-path: an INFERENCE node has no model_path.

What it checks:
    Every INFERENCE node sets `model_path`: a policy directory written by save_pretrained, or
    `registry:NAME[@REVISION]`.

Why it matters:
    An inference node without a policy cannot produce actions.

Example:
    node {
      type: INFERENCE            # error: INFERENCE node "inference" has no model_path
      topic_name: "/arm/commands"
      input_topics: ["/arm/joint_states"]
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E107"
NAME = "missing-model-path"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.lacking("model_path"):
        yield Finding(view.path, f"{view.label} has no model_path")
