"""Turn an MCAP bag into a LeRobot v3.0 dataset of one episode, as the recorder would have recorded it live.

The bag's messages are replayed in time order into the latest message of each chosen topic; a frame
is taken every 1/fps seconds of bag time from the first message on, with the recorder's own rules
(frame_sampler.py: the action topic, JointState inputs as observation.state, Image inputs as
observation.images.<key>, the joint values in `units`). A tick at which a topic has not published
yet, or last published more than STALE_AFTER_S before, gives no frame (counted as skipped).
"""

from dataclasses import dataclass, field
from pathlib import Path

from joshua_core.settings import TopicSettings
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.frame_sampler import FrameSampler, FrameUnavailable
from joshua_runtime.ai.lerobot_units import SI, JointUnits
from joshua_runtime.bags.bag_reader import Bag, open_bag
from joshua_runtime.errors import SettingsError
from joshua_runtime.messages import message_class

STALE_AFTER_S = 0.5  # as the recorder's SAMPLE_STALE_AFTER_S
NS_PER_S = 1_000_000_000
PARTIAL_SUFFIX = ".partial"


@dataclass
class Conversion:
    bag: Path
    output: Path
    action: str
    inputs: list[str]
    fps: int
    task: str
    robot_type: str = ""
    use_videos: bool = False
    units: str = SI
    calibration_file: str = ""
    frames: int = field(default=0, init=False)
    skipped: int = field(default=0, init=False)


def _topics(bag: Bag, conversion: Conversion) -> list[TopicSettings]:
    chosen = [conversion.action, *conversion.inputs]
    missing = [topic for topic in chosen if topic not in bag.topics]
    if missing:
        raise SettingsError(f"{bag.path} has no topic {', '.join(missing)} (it has {', '.join(sorted(bag.topics))})")
    if bag.topics[conversion.action].message_type != keys.JOINT_STATE:
        raise SettingsError(
            f"the action topic {conversion.action} is a {bag.topics[conversion.action].message_type}, not a {keys.JOINT_STATE}"
        )
    inputs = [TopicSettings(name=topic, message_type=bag.topics[topic].message_type) for topic in conversion.inputs]
    keys.check_inputs("from-bag", inputs)
    return inputs


def convert(conversion: Conversion) -> Conversion:
    """Write the dataset at conversion.output (which must not exist); the counts of frames taken and skipped."""
    from rclpy.serialization import deserialize_message

    output = conversion.output
    if output.exists():
        raise SettingsError(f"{output} exists; give a new directory for the dataset")
    bag = open_bag(conversion.bag)
    inputs = _topics(bag, conversion)
    units = JointUnits(conversion.units, conversion.calibration_file)
    sampler = FrameSampler(conversion.action, inputs, conversion.use_videos, units)
    classes = {topic: message_class(bag.topics[topic].message_type) for topic in sampler.topic_names}
    latest: dict[str, tuple[int, object]] = {}
    frames: list[dict] = []
    period_ns = NS_PER_S // conversion.fps
    tick_ns = bag.start_ns

    def take(at_ns: int) -> None:
        fresh = all(t in latest and at_ns - latest[t][0] <= STALE_AFTER_S * NS_PER_S for t in sampler.topic_names)
        try:
            if not fresh:
                raise FrameUnavailable("a topic has no recent message")
            frames.append(sampler.frame(lambda topic: latest[topic][1]))
        except FrameUnavailable:
            conversion.skipped += 1

    for topic, data, log_time in bag.messages(sampler.topic_names):
        while tick_ns < log_time:
            take(tick_ns)
            tick_ns += period_ns
        latest[topic] = (log_time, deserialize_message(data, classes[topic]))
    if latest and tick_ns == max(at for at, _ in latest.values()):
        take(tick_ns)  # a tick at the bag's last message; none after it
    if not frames:
        raise SettingsError(f"{bag.path}: no frame with every chosen topic fresh (within {STALE_AFTER_S:g} s)")
    _write(conversion, sampler.features, frames)
    conversion.frames = len(frames)
    return conversion


def _write(conversion: Conversion, features: dict, frames: list[dict]) -> None:
    import shutil

    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    partial = conversion.output.with_name(conversion.output.name + PARTIAL_SUFFIX)
    shutil.rmtree(partial, ignore_errors=True)
    try:
        dataset = LeRobotDataset.create(
            f"local/{conversion.output.name}",
            conversion.fps,
            features,
            root=partial,
            robot_type=conversion.robot_type or None,
            use_videos=conversion.use_videos,
            video_backend="pyav",
        )
        for frame in frames:
            dataset.add_frame(dict(frame, task=conversion.task))
        dataset.save_episode()
        dataset.finalize()
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        raise
    partial.rename(conversion.output)
