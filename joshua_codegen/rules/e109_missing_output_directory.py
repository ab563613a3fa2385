"""E109 missing-output-directory: a DATA_SUBSCRIBER node has no output_directory.

What it checks:
    Every DATA_SUBSCRIBER node sets `output_directory`: where the dataset is written.

Why it matters:
    A recorder without a destination would lose every episode.

Example:
    node {
      type: DATA_SUBSCRIBER      # error: DATA_SUBSCRIBER node "data_subscriber" has no output_directory
      topic_name: "/leader/joint_states"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E109"
NAME = "missing-output-directory"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.lacking("output_directory"):
        yield Finding(view.path, f"{view.label} has no output_directory")
