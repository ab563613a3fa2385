"""E108 missing-input-topics: an INFERENCE node reads no input_topics.

What it checks:
    Every INFERENCE node lists at least one `input_topics` entry: the observations the policy reads.

Why it matters:
    A policy with no observations cannot run.

Example:
    node {
      type: INFERENCE            # error: INFERENCE node "inference" reads no input_topics
      topic_name: "/arm/commands"
      model_path: "/models/act"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E108"
NAME = "missing-input-topics"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.lacking("input_topics"):
        yield Finding(view.path, f'{view.label} reads no input_topics '
                                 '(e.g. input_topics: ["/camera/image_raw", "/arm/joint_states"])')
