"""Names both sides agree on for models and data: built-in MJCF models, GL backends, policy types, output formats
and the model-registry prefix, and what message types a reader takes."""

from joshua_core.node_families import Family
from joshua_core.node_types import BASE_WHEEL_JOINTS, NodeTypeSpec
from joshua_core.so100 import SO100_JOINTS

# `simulation { model: "builtin:NAME" }` names an MJCF model shipped with joshua_runtime.
BUILTIN_PREFIX = "builtin:"
BUILTIN_MODELS = ("so100", "lego_bot")
# The hinge joints of each built-in model: a simulated servo node's or base's joint_names must be among them.
BUILTIN_MODEL_JOINTS = {"so100": SO100_JOINTS, "lego_bot": BASE_WHEEL_JOINTS}
# Offscreen GL backends the simulation can render with; the first is the default.
GL_BACKENDS = ("egl", "osmesa")
# `model_path: "registry:NAME[@REVISION]"` names a policy in the local model registry.
REGISTRY_PREFIX = "registry:"
# What DATA_SUBSCRIBER writes (`output_format`); the first is the default. BAG_FORMAT records ROS
# messages as they are (a rosbag2 MCAP bag), so it takes inputs of any type.
BAG_FORMAT = "mcap"
OUTPUT_FORMATS = ("lerobot", "parquet", BAG_FORMAT)
# LeRobot policy types an INFERENCE node can run (`policy_type`, compared without case; a saved policy's
# config.json names its type, and the node refuses any other).
POLICY_TYPES = ("act", "diffusion", "smolvla")
# The URDF a ROBOT_STATE_PUBLISHER publishes when `robot_description` is unset (shipped with joshua_runtime).
DEFAULT_ROBOT_DESCRIPTION = "builtin:so100"
# Torch devices an INFERENCE node runs a policy on (`device`); the first is the default.
DEVICES = ("cpu", "cuda")
# Where the registry lives: $JOSHUA_MODEL_REGISTRY, else REGISTRY_DEFAULT_ROOT (with ~ expanded); an entry
# is <root>/<name>/<revision>/ holding REGISTRY_ENTRY_FILE. supervisor.py's preflight resolves it too.
REGISTRY_ENV = "JOSHUA_MODEL_REGISTRY"
REGISTRY_DEFAULT_ROOT = "~/.cache/joshua/models"
REGISTRY_ENTRY_FILE = "joshua_model.json"


def readable_input_types(entry: NodeTypeSpec, output_format: str) -> tuple[str, ...] | None:
    """The message types a node's input_topics may carry; None when any type is fine.

    A recorder writing a ROS bag stores messages as they are, whatever their type; every other
    reader (a policy, a dataset recorder) reads only its registry entry's input_types.
    """
    if entry.family == Family.RECORDER and output_format == BAG_FORMAT:
        return None
    return entry.input_types
