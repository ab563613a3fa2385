"""Build a policy observation from the latest ROS messages of an INFERENCE node's inputs.

Rule (the recording side uses the same, see `features.py`):
- Each policy image feature `observation.images.<key>` is fed by the Image input whose topic maps to
  `<key>`. When the policy has a single image feature and the node a single Image input, they are
  paired whatever their names. Images of another size than the policy's are resized (images.resize, the
  function `joshua-train imitation --image-size` resizes the training frames with).
- `observation.state` is the positions of the JointState inputs concatenated in input order. When
  the policy's state names are known (`<joint>.pos`, from the dataset it was trained on), each value
  is instead picked by joint name from the inputs, so the order of joints in messages does not matter.
"""

import numpy as np

from joshua_core.settings import TopicSettings
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.images import resize as resize_image
from joshua_runtime.ai.ros_arrays import image_to_rgb, joint_positions
from joshua_runtime.errors import SettingsError


class ObservationUnavailable(ValueError):
    """The latest messages cannot form an observation (wrong size, missing joint, bad encoding)."""


class ObservationMapper:
    """Maps input topics to policy features once, then converts messages on every step."""

    def __init__(
        self,
        node_name: str,
        inputs: list[TopicSettings],
        images: dict[str, tuple[int, ...]],
        state_size: int | None,
        state_names: list[str] | None = None,
    ):
        image_topics = [t.name for t in inputs if t.message_type in keys.IMAGE_TYPES]
        self.state_topics = [t.name for t in inputs if t.message_type == keys.JOINT_STATE]
        self.image_sources = _pair_images(node_name, image_topics, images)
        self.image_shapes = images
        self.state_size = state_size
        if state_size is not None and not self.state_topics:
            raise SettingsError(f"{node_name}: the policy reads observation.state but no JointState input is given")
        usable_names = state_names if state_names and len(state_names) == state_size else None
        self.state_joints = [keys.joint_name(name) for name in usable_names] if usable_names else None
        self.unused_topics = [t for t in image_topics if t not in self.image_sources.values()]

    def observation(self, message_of) -> dict[str, np.ndarray]:
        """The observation dict from `message_of(topic_name)` -> latest message."""
        observation = {}
        for feature, topic in self.image_sources.items():
            try:
                pixels = image_to_rgb(message_of(topic))
            except ValueError as exc:
                raise ObservationUnavailable(f"{topic}: {exc}") from exc
            channels, height, width = self.image_shapes[feature]
            observation[feature] = resize_image(pixels, width, height)
        if self.state_size is not None:
            observation[keys.STATE] = self._state(message_of)
        return observation

    def _state(self, message_of) -> np.ndarray:
        pairs = [joint_positions(message_of(topic)) for topic in self.state_topics]
        if self.state_joints is not None:
            by_name = {}
            for names, values in pairs:
                by_name.update(zip(names, values))
            missing = [joint for joint in self.state_joints if joint not in by_name]
            if not missing:
                return np.array([by_name[joint] for joint in self.state_joints], dtype=np.float32)
        values = np.concatenate([values for _, values in pairs]) if pairs else np.zeros(0, np.float32)
        if values.size != self.state_size:
            raise ObservationUnavailable(
                f"JointState inputs give {values.size} positions, the policy expects {self.state_size}"
            )
        return values.astype(np.float32)


def _pair_images(node_name: str, topics: list[str], images: dict[str, tuple[int, ...]]) -> dict[str, str]:
    if len(images) == 1 and len(topics) == 1:
        return {next(iter(images)): topics[0]}
    by_feature = {keys.image_feature(topic): topic for topic in topics}
    missing = [feature for feature in images if feature not in by_feature]
    if missing:
        wanted = ", ".join(f"{f} (e.g. topic /{f[len(keys.IMAGE_PREFIX) :]}/image_raw)" for f in missing)
        raise SettingsError(f"{node_name}: no Image input for policy feature {wanted}")
    return {feature: by_feature[feature] for feature in images}
