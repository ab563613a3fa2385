"""The one mapping rule between ROS topics and LeRobot feature keys, shared by recording and inference.

- A `sensor_msgs/msg/JointState` topic recorded by a DATA_SUBSCRIBER as its `topic` becomes `action`;
  an INFERENCE node publishes `action` on its `topic` the same way.
- `sensor_msgs/msg/JointState` inputs become `observation.state`: the positions of every JointState
  input, concatenated in the order the inputs are listed, each in the order of the message's `name`.
  Feature names are `<joint>.pos` (LeRobot's SO-100 convention).
- `sensor_msgs/msg/Image` (or `CompressedImage`) inputs become `observation.images.<key>`
  (joshua_core/feature_keys.py: `/camera/image_raw` -> `camera`).
"""

from joshua_core.feature_keys import IMAGE_PREFIX, image_feature, image_key  # noqa: F401 (part of this mapping)
from joshua_core.message_types import IMAGE_TYPES, OBSERVATION_TYPES
from joshua_core.message_types import JOINT_STATE as JOINT_STATE  # keys.JOINT_STATE for the recorder and inference
from joshua_core.settings import TopicSettings
from joshua_runtime.errors import SettingsError

ACTION = "action"
STATE = "observation.state"
POSITION_SUFFIX = ".pos"


def position_names(joint_names: list[str]) -> list[str]:
    """LeRobot feature names of joint positions: `shoulder_pan` -> `shoulder_pan.pos`."""
    return [name + POSITION_SUFFIX for name in joint_names]


def joint_name(feature_name: str) -> str:
    """The joint of a feature name: `shoulder_pan.pos` -> `shoulder_pan` (other names unchanged)."""
    return feature_name[: -len(POSITION_SUFFIX)] if feature_name.endswith(POSITION_SUFFIX) else feature_name


def check_inputs(node_name: str, inputs: list[TopicSettings]) -> None:
    """Reject inputs of unsupported message types and Image inputs that map to the same key."""
    seen: dict[str, str] = {}
    for topic in inputs:
        kind = topic.message_type
        if kind not in OBSERVATION_TYPES:
            raise SettingsError(
                f"{node_name}: input {topic.name} has message type {kind or '(unknown)'}; "
                f"supported: {', '.join(OBSERVATION_TYPES)}"
            )
        if kind in IMAGE_TYPES:
            feature = image_feature(topic.name)
            if feature in seen:
                raise SettingsError(f"{node_name}: inputs {seen[feature]} and {topic.name} both map to {feature}")
            seen[feature] = topic.name
