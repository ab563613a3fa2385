"""E108 missing-input-topics: an INFERENCE or DATA_SUBSCRIBER node reads no input_topics.

What it checks:
    Every INFERENCE and DATA_SUBSCRIBER node lists at least one `input_topics` entry: the
    observations (images, joint states) the policy reads or the recorder writes next to the action.

Why it matters:
    A policy with no observations cannot run. A dataset of actions alone cannot train a policy:
    LeRobot refuses it ("You must provide at least one image or the environment state").

Example:
    node {
      type: INFERENCE            # error: INFERENCE node "inference" reads no input_topics
      topic_name: "/arm/commands"
      model_path: "/models/act"
    }
    node {
      type: DATA_SUBSCRIBER      # error: DATA_SUBSCRIBER node "data_subscriber" records no observations
      topic_name: "/leader/joint_states"
      output_directory: "/data/episodes"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E108"
NAME = "missing-input-topics"
SEVERITY = ERROR
STAGE = "check"
EXAMPLE = 'input_topics: ["/camera/image_raw", "/arm/joint_states"]'


def check(ctx):
    for view in ctx.lacking("input_topics"):
        if view.node.type == pb.DATA_SUBSCRIBER:
            yield Finding(
                view.path,
                f"{view.label} records no observations, so its dataset has nothing to train "
                f"on: list the images and joint states to record (e.g. {EXAMPLE})",
            )
        else:
            yield Finding(view.path, f"{view.label} reads no input_topics (e.g. {EXAMPLE})")
