"""Turn the latest messages of a recorder's topics into LeRobot frames (one per tick, same layout each time).

The layout follows `features.py`: the recorded JointState `topic` is `action`, JointState inputs
are `observation.state` (in input order), Image inputs are `observation.images.<key>`. It is fixed
by the first complete set of messages: joint names, joint order and image sizes. Later messages
are read by joint name, so a publisher that reorders its joints is still recorded correctly; a
missing joint or a changed image size makes the frame unavailable. Joint positions are written in the
convention of `units` (lerobot_units.py; radians when none is given).
"""

import numpy as np

from joshua_core.settings import TopicSettings
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.lerobot_units import SI, JointUnits
from joshua_runtime.ai.ros_arrays import image_to_rgb, joint_positions

IMAGE_NAMES = ["height", "width", "channels"]


class FrameUnavailable(ValueError):
    """The latest messages do not fit the dataset layout."""


class FrameSampler:
    """Builds LeRobot feature definitions once, then a frame dict per call."""

    def __init__(
        self, action_topic: str, inputs: list[TopicSettings], use_videos: bool, units: JointUnits | None = None
    ):
        self.action_topic = action_topic
        self.units = units or JointUnits(SI)
        self.state_topics = [t.name for t in inputs if t.message_type == keys.JOINT_STATE]
        self.image_topics = {keys.image_feature(t.name): t.name for t in inputs if t.message_type in keys.IMAGE_TYPES}
        self.image_dtype = "video" if use_videos else "image"
        self.joints: dict[str, list[str]] = {}
        self.image_shapes: dict[str, tuple[int, int, int]] = {}
        self.features: dict | None = None

    @property
    def topic_names(self) -> list[str]:
        return [self.action_topic, *self.state_topics, *self.image_topics.values()]

    def frame(self, message_of) -> dict:
        """A frame from `message_of(topic) -> latest message`; defines the features on first use."""
        if self.features is None:
            self._define(message_of)
        frame = {keys.ACTION: self._positions(self.action_topic, message_of)}
        if self.state_topics:
            frame[keys.STATE] = np.concatenate([self._positions(topic, message_of) for topic in self.state_topics])
        for feature, topic in self.image_topics.items():
            try:
                pixels = image_to_rgb(message_of(topic))
            except ValueError as exc:
                raise FrameUnavailable(f"{topic}: {exc}") from exc
            if pixels.shape != self.image_shapes[feature]:
                raise FrameUnavailable(
                    f"{topic}: image is {pixels.shape}, the dataset records {self.image_shapes[feature]}"
                )
            frame[feature] = pixels
        return frame

    def _positions(self, topic: str, message_of) -> np.ndarray:
        names, values = joint_positions(message_of(topic))
        wanted = self.joints[topic]
        if names != wanted:
            by_name = dict(zip(names, values))
            missing = [joint for joint in wanted if joint not in by_name]
            if missing:
                raise FrameUnavailable(f"{topic}: joint(s) {', '.join(missing)} missing")
            values = np.array([by_name[joint] for joint in wanted], dtype=np.float32)
        return self.units.from_radians(wanted, values)

    def _define(self, message_of) -> None:
        for topic in [self.action_topic, *self.state_topics]:
            names, values = joint_positions(message_of(topic))
            if not names or len(names) != len(values):
                raise FrameUnavailable(f"{topic}: a JointState needs one name per position")
            self.units.check_joints(names)
            self.joints[topic] = names
        features = {keys.ACTION: _vector(self.joints[self.action_topic])}
        if self.state_topics:
            features[keys.STATE] = _vector([j for topic in self.state_topics for j in self.joints[topic]])
        for feature, topic in self.image_topics.items():
            try:
                shape = image_to_rgb(message_of(topic)).shape
            except ValueError as exc:
                raise FrameUnavailable(f"{topic}: {exc}") from exc
            self.image_shapes[feature] = shape
            features[feature] = {"dtype": self.image_dtype, "shape": shape, "names": IMAGE_NAMES}
        self.features = features


def _vector(joints: list[str]) -> dict:
    return {"dtype": "float32", "shape": (len(joints),), "names": keys.position_names(joints)}
