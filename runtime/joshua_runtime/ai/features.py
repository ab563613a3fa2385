"""The one mapping rule between ROS topics and LeRobot feature keys, shared by recording and inference.

- A `sensor_msgs/msg/JointState` topic recorded by a DATA_SUBSCRIBER as its `topic` becomes `action`;
  an INFERENCE node publishes `action` on its `topic` the same way.
- `sensor_msgs/msg/JointState` inputs become `observation.state`: the positions of every JointState
  input, concatenated in the order the inputs are listed, each in the order of the message's `name`.
  Feature names are `<joint>.pos` (LeRobot's SO-100 convention).
- `sensor_msgs/msg/Image` (or `CompressedImage`) inputs become `observation.images.<key>`, where `<key>` is the topic name
  without its leading slash and without a last segment starting with `image` (`image_raw`,
  `image_rect`, ...), the remaining segments joined by `_`:
  `/camera/image_raw` -> `camera`, `/arm/wrist/image` -> `arm_wrist`, `/front` -> `front`.
"""

import re

from joshua_core.node_types import IMAGE_TYPES, JOINT_STATE, OBSERVATION_TYPES
from joshua_core.settings import TopicSettings
from joshua_runtime.errors import SettingsError


ACTION = "action"
STATE = "observation.state"
IMAGE_PREFIX = "observation.images."
POSITION_SUFFIX = ".pos"

_NOT_KEY_CHARACTER = re.compile(r"[^A-Za-z0-9_]")


def image_key(topic_name: str) -> str:
    """The `<key>` of `observation.images.<key>` for an Image topic (see the module docstring)."""
    parts = [part for part in topic_name.split("/") if part]
    if len(parts) > 1 and parts[-1].startswith("image"):
        parts = parts[:-1]
    key = _NOT_KEY_CHARACTER.sub("_", "_".join(parts))
    return key or "image"


def image_feature(topic_name: str) -> str:
    """`observation.images.<key>` for an Image topic."""
    return IMAGE_PREFIX + image_key(topic_name)


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
                raise SettingsError(
                    f"{node_name}: inputs {seen[feature]} and {topic.name} both map to {feature}"
                )
            seen[feature] = topic.name
