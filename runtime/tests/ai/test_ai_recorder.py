"""The DATA_SUBSCRIBER node as a real process: episodes by command, SIGINT and SIGKILL, both formats."""

import signal
import time

import numpy as np
import pytest
from ai_support import (
    IMAGE,
    RELIABLE,
    NodeProcess,
    compiled,
    mock_camera,
    mock_encoder,
    node_block,
    pattern_image,
    topic,
)
from sensor_msgs.msg import Image, JointState
from std_msgs.msg import String

RATE_HZ = 10.0
PUBLISH_HZ = 30.0
HEIGHT, WIDTH = 24, 32
JOINTS = ["shoulder_pan", "gripper"]
RECORDING_S = 0.6
SETTLE_S = 0.3
# Largest mean absolute pixel error allowed after AV1 encoding of the smooth test image.
VIDEO_PIXEL_TOLERANCE = 6.0


class Sensors:
    """Synthetic leader, follower and camera whose values depend on the current phase."""

    def __init__(self, peer):
        from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

        self.phase = 0
        self.timers = {
            "leader": peer.publish_periodically(
                "/rec/leader/joint_states", JointState, PUBLISH_HZ, lambda: joint_state(JOINTS, self.action())
            ),
            "follower": peer.publish_periodically(
                "/rec/follower/joint_states", JointState, PUBLISH_HZ, lambda: joint_state(JOINTS, self.state())
            ),
            "camera": peer.publish_periodically(
                "/rec/camera/image_raw", Image, PUBLISH_HZ, lambda: rgb_to_image(self.image())
            ),
        }

    def action(self, phase=None):
        phase = self.phase if phase is None else phase
        return np.array([phase, -phase], np.float32)

    def state(self, phase=None):
        phase = self.phase if phase is None else phase
        return np.array([phase + 0.5, 0.25 * phase], np.float32)

    def image(self, phase=None):
        return pattern_image(HEIGHT, WIDTH, 40 * (self.phase if phase is None else phase))

    def set_phase(self, phase: int) -> None:
        self.phase = phase
        time.sleep(SETTLE_S)  # let the held samples of the recorder catch up with the new values


def recorder_settings(output, output_format):
    """The recorder's settings as joshuac writes them; the mock publishers only give the topics their
    types (this test publishes the values itself, to know them)."""
    return compiled(
        "MODE_DATA_COLLECTION",
        mock_camera("camera", "/rec/camera/image_raw", WIDTH, HEIGHT, PUBLISH_HZ),
        mock_encoder("leader", "/rec/leader/joint_states", JOINTS, PUBLISH_HZ),
        mock_encoder("follower", "/rec/follower/joint_states", JOINTS, PUBLISH_HZ),
        node_block(
            "ai_recorder",
            "DATA_SUBSCRIBER",
            topic_name="/rec/leader/joint_states",
            input_topics=["/rec/camera/image_raw", "/rec/follower/joint_states"],
            output_directory=str(output),
            output_format=output_format,
            rate_hz=RATE_HZ,
        ),
    )["ai_recorder"]


def send(peer, publisher, text):
    peer.send_text(publisher, text)


def record_one(node, mark):
    """Wait for the episode's first frame, then let it record a little."""
    node.wait_for("first frame of the episode recorded", after=mark)
    time.sleep(RECORDING_S)


def load(root):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    return LeRobotDataset("local/test", root=root, video_backend="pyav")


def episode_rows(dataset, episode):
    start = dataset.meta.episodes[episode]["dataset_from_index"]
    stop = dataset.meta.episodes[episode]["dataset_to_index"]
    return [dataset[i] for i in range(start, stop)]


def check_episode(dataset, episode, phase, frames, sensors, exact_images):
    rows = episode_rows(dataset, episode)
    assert len(rows) == frames
    assert [int(row["frame_index"]) for row in rows] == list(range(frames))
    for row in rows:
        assert np.array_equal(row["action"].numpy(), sensors.action(phase))
        assert np.array_equal(row["observation.state"].numpy(), sensors.state(phase))
    for row in (rows[0], rows[-1]):
        pixels = (row["observation.images.rec_camera"].permute(1, 2, 0).numpy() * 255).round()
        expected = sensors.image(phase).astype(np.float64)
        if exact_images:
            assert np.array_equal(pixels, expected)
        else:
            assert np.abs(pixels - expected).mean() < VIDEO_PIXEL_TOLERANCE


def test_episodes_by_command_and_sigint_saves_the_episode_in_progress(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    sensors = Sensors(ros_peer)
    commands = ros_peer.publisher("/ai_recorder/episode", String, RELIABLE)
    node = NodeProcess(recorder_settings(output, "lerobot"), ai_env)
    try:
        node.wait_for(r"recording 3 topics at 10 fps .*episode commands on /ai_recorder/episode")
        record_one(node, 0)  # episode 0 starts with the node
        mark = node.count()
        send(ros_peer, commands, "stop")
        saved = [int(node.wait_for(r"episode 0 saved: (\d+) frames", after=mark).group(1))]

        sensors.set_phase(1)
        mark = node.count()
        send(ros_peer, commands, "start")
        record_one(node, mark)
        send(ros_peer, commands, "discard")
        node.wait_for(r"episode discarded", after=mark)

        sensors.set_phase(2)
        mark = node.count()
        send(ros_peer, commands, "start pick the cube")
        record_one(node, mark)
        send(ros_peer, commands, "stop")
        saved.append(int(node.wait_for(r"episode 1 saved: (\d+) frames", after=mark).group(1)))

        sensors.set_phase(3)
        mark = node.count()
        send(ros_peer, commands, "start")
        record_one(node, mark)
        sensors.timers["camera"].cancel()  # the camera goes silent: frames are skipped
        node.wait_for(r"frame skipped: /rec/camera/image_raw is stale", after=mark)
        assert node.stop(signal.SIGINT) == 0
        saved.append(int(node.wait_for(r"episode 2 saved: (\d+) frames", after=mark).group(1)))
    finally:
        node.kill()

    dataset = load(output)
    assert dataset.meta.total_episodes == 3 and dataset.num_episodes == 3
    assert dataset.meta.total_frames == sum(saved) == len(dataset)
    assert min(saved) > 0
    assert dataset.fps == 10 and dataset.meta.robot_type == "test_arm"
    features = dataset.meta.features
    assert features["action"]["names"] == ["shoulder_pan.pos", "gripper.pos"]
    assert features["observation.state"]["names"] == ["shoulder_pan.pos", "gripper.pos"]
    assert features["observation.images.rec_camera"]["dtype"] == "video"
    assert tuple(features["observation.images.rec_camera"]["shape"]) == (HEIGHT, WIDTH, 3)
    assert dataset.meta.video_keys == ["observation.images.rec_camera"]
    for episode, phase in enumerate((0, 2, 3)):
        check_episode(dataset, episode, phase, saved[episode], sensors, exact_images=False)
    assert [dataset.meta.episodes[e]["tasks"] for e in range(3)] == [["test_arm"], ["pick the cube"], ["test_arm"]]
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("dataset")) == ["dataset"]


def test_sigkill_loses_only_the_episode_in_progress_and_recording_resumes(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    sensors = Sensors(ros_peer)
    commands = ros_peer.publisher("/ai_recorder/episode", String, RELIABLE)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)
    try:
        record_one(node, 0)
        mark = node.count()
        send(ros_peer, commands, "stop")
        first = int(node.wait_for(r"episode 0 saved: (\d+) frames", after=mark).group(1))
        sensors.set_phase(1)
        mark = node.count()
        send(ros_peer, commands, "start")
        record_one(node, mark)
        node.process.kill()  # SIGKILL in the middle of episode 1
        assert node.process.wait() == -signal.SIGKILL
    finally:
        node.kill()

    dataset = load(output)
    assert dataset.meta.total_episodes == 1 and len(dataset) == first
    check_episode(dataset, 0, 0, first, sensors, exact_images=True)

    sensors.set_phase(2)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)  # resumes the same dataset
    try:
        record_one(node, 0)
        assert node.stop(signal.SIGINT) == 0
        second = int(node.wait_for(r"episode 1 saved: (\d+) frames").group(1))
    finally:
        node.kill()

    dataset = load(output)
    assert dataset.meta.total_episodes == 2 and len(dataset) == first + second
    features = dataset.meta.features
    assert features["observation.images.rec_camera"]["dtype"] == "image"
    assert dataset.meta.video_keys == []
    check_episode(dataset, 0, 0, first, sensors, exact_images=True)
    check_episode(dataset, 1, 2, second, sensors, exact_images=True)
    assert not (output / "videos").exists() and not (output / "images").exists()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("dataset")) == ["dataset"]


def other_files(output):
    output.mkdir()
    (output / "notes.txt").write_text("not a dataset")


def dataset_at_30_fps(output):
    (output / "meta").mkdir(parents=True)
    (output / "meta" / "info.json").write_text('{"fps": 30}')


@pytest.mark.parametrize(
    ("overrides", "prepare", "message"),
    [
        ({"output_format": "hdf5"}, None, "output_format 'hdf5' is not one of lerobot, parquet"),
        ({"output_directory": ""}, None, "ai_recorder: output_directory is empty"),
        (
            {"topic": topic("/rec/camera/image_raw", IMAGE)},
            None,
            "the recorded topic must be sensor_msgs/msg/JointState",
        ),
        (
            {"inputs": [topic("/scan", "sensor_msgs/msg/LaserScan")]},
            None,
            "input /scan has message type sensor_msgs/msg/LaserScan",
        ),
        ({}, other_files, "output_directory {output} is not empty and holds no LeRobot dataset"),
        ({}, dataset_at_30_fps, "output_directory {output} holds a dataset recorded at 30 fps, not 10"),
    ],
)
def test_unusable_settings_exit_2_with_one_line(tmp_path, ai_env, overrides, prepare, message):
    """Settings joshuac refuses (changed after compiling) and unusable output directories: one line, exit 2."""
    output = tmp_path / "dataset"
    if prepare is not None:
        prepare(output)
    before = sorted(output.rglob("*")) if output.exists() else None
    settings = recorder_settings(output, "lerobot")
    settings.update(overrides)
    node = NodeProcess(settings, ai_env)
    assert node.process.wait(timeout=60) == 2
    node._reader.join()
    assert len(node.lines) == 1 and node.lines[0].startswith("ai_recorder: error: ")
    assert message.format(output=output) in node.lines[0]
    assert (sorted(output.rglob("*")) if output.exists() else None) == before
