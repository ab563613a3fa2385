"""Pure parts of the AI layer: the topic/feature rule, message arrays, frames, observations, staging."""

import os
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from joshua_core.settings import TopicSettings
from joshua_runtime.ai import features, staged_directory
from joshua_runtime.ai.frame_sampler import FrameSampler, FrameUnavailable
from joshua_runtime.ai.inference_node import action_joint_names
from joshua_runtime.ai.observation_mapper import ObservationMapper, ObservationUnavailable
from joshua_runtime.ai.ros_arrays import ImageFormatError, image_to_bgr, image_to_rgb
from joshua_runtime.errors import SettingsError

IMAGE = "sensor_msgs/msg/Image"
JOINT_STATE = "sensor_msgs/msg/JointState"


def image_message(rgb: np.ndarray, encoding="rgb8", padding=0):
    channels = {"rgb8": rgb, "bgr8": rgb[:, :, ::-1], "mono8": rgb[:, :, :1]}[encoding]
    height, width, depth = channels.shape
    rows = np.zeros((height, width * depth + padding), np.uint8)
    rows[:, : width * depth] = channels.reshape(height, -1)
    return SimpleNamespace(
        encoding=encoding, height=height, width=width, step=width * depth + padding, data=rows.tobytes()
    )


def joints(names, positions):
    return SimpleNamespace(name=list(names), position=list(positions))


@pytest.mark.parametrize(
    ("topic_name", "key"),
    [
        ("/camera/image_raw", "camera"),
        ("/arm/wrist/image", "arm_wrist"),
        ("/camera/image_raw/compressed", "camera"),  # image_transport's JPEG copy names the same camera
        ("/front/compressed", "front"),
        ("/compressed", "compressed"),
        ("/front", "front"),
        ("/cam.left/image_rect", "cam_left"),
        ("/image_raw", "image_raw"),
        ("/", "image"),
    ],
)
def test_image_topics_map_to_feature_keys(topic_name, key):
    assert features.image_key(topic_name) == key
    assert features.image_feature(topic_name) == f"observation.images.{key}"


def test_inputs_of_other_types_or_same_key_are_refused():
    with pytest.raises(SettingsError, match="input /scan has message type sensor_msgs/msg/LaserScan"):
        features.check_inputs("n", [TopicSettings(name="/scan", message_type="sensor_msgs/msg/LaserScan")])
    same = [
        TopicSettings(name="/cam/image_raw", message_type=IMAGE),
        TopicSettings(name="/cam/image_rect", message_type=IMAGE),
    ]
    with pytest.raises(
        SettingsError, match="inputs /cam/image_raw and /cam/image_rect both map to observation.images.cam"
    ):
        features.check_inputs("n", same)


def test_images_of_every_encoding_become_rgb():
    rgb = np.random.default_rng(0).integers(0, 256, (5, 7, 3), dtype=np.uint8)
    assert np.array_equal(image_to_rgb(image_message(rgb)), rgb)
    assert np.array_equal(image_to_rgb(image_message(rgb, "bgr8", padding=3)), rgb)
    mono = image_to_rgb(image_message(rgb, "mono8"))
    assert mono.shape == (5, 7, 3) and np.array_equal(mono[:, :, 2], rgb[:, :, 0])
    png = cv2.imencode(".png", rgb[:, :, ::-1])[1].tobytes()
    assert np.array_equal(image_to_rgb(SimpleNamespace(format="png", data=png)), rgb)
    with pytest.raises(ImageFormatError, match="unsupported image encoding '16UC1'"):
        image_to_rgb(SimpleNamespace(encoding="16UC1", height=1, width=1, step=2, data=b"\0\0"))
    short = image_message(rgb)
    short.data = short.data[:-1]
    with pytest.raises(ImageFormatError, match="has 104 bytes"):
        image_to_rgb(short)


def test_images_of_every_encoding_become_bgr_for_opencv_and_never_share_the_message():
    rgb = np.random.default_rng(1).integers(0, 256, (5, 7, 3), dtype=np.uint8)
    for encoding, padding in (("rgb8", 0), ("bgr8", 3), ("rgb8", 2)):
        message = image_message(rgb, encoding, padding)
        bgr = image_to_bgr(message)
        assert np.array_equal(bgr, rgb[:, :, ::-1]) and bgr.flags.c_contiguous
        assert not np.shares_memory(bgr, np.frombuffer(message.data, np.uint8))
        assert not np.shares_memory(image_to_rgb(message), np.frombuffer(message.data, np.uint8))
    mono = image_to_bgr(image_message(rgb, "mono8"))
    assert mono.shape == (5, 7, 3) and np.array_equal(mono[:, :, 0], rgb[:, :, 0])


def test_frames_follow_the_first_layout_and_read_joints_by_name():
    inputs = [
        TopicSettings(name="/cam/image_raw", message_type=IMAGE),
        TopicSettings(name="/follower", message_type=JOINT_STATE),
    ]
    sampler = FrameSampler("/leader", inputs, use_videos=True)
    rgb = np.full((4, 6, 3), 9, np.uint8)
    latest = {
        "/leader": joints(["a", "b"], [1, 2]),
        "/follower": joints(["a", "b"], [3, 4]),
        "/cam/image_raw": image_message(rgb),
    }
    frame = sampler.frame(latest.__getitem__)
    assert sampler.features == {
        "action": {"dtype": "float32", "shape": (2,), "names": ["a.pos", "b.pos"]},
        "observation.state": {"dtype": "float32", "shape": (2,), "names": ["a.pos", "b.pos"]},
        "observation.images.cam": {"dtype": "video", "shape": (4, 6, 3), "names": ["height", "width", "channels"]},
    }
    assert frame["action"].tolist() == [1, 2] and frame["observation.state"].tolist() == [3, 4]
    latest["/leader"] = joints(["b", "a"], [20, 10])
    assert sampler.frame(latest.__getitem__)["action"].tolist() == [10, 20]
    latest["/leader"] = joints(["a"], [1])
    with pytest.raises(FrameUnavailable, match="/leader: joint\\(s\\) b missing"):
        sampler.frame(latest.__getitem__)
    latest["/leader"] = joints(["a", "b"], [1, 2])
    latest["/cam/image_raw"] = image_message(np.zeros((5, 6, 3), np.uint8))
    with pytest.raises(FrameUnavailable, match="image is \\(5, 6, 3\\), the dataset records \\(4, 6, 3\\)"):
        sampler.frame(latest.__getitem__)


def test_observations_pair_images_and_pick_state_by_joint_name():
    inputs = [
        TopicSettings(name="/top/image_raw", message_type=IMAGE),
        TopicSettings(name="/wrist/image_raw", message_type=IMAGE),
        TopicSettings(name="/arm", message_type=JOINT_STATE),
        TopicSettings(name="/gripper", message_type=JOINT_STATE),
    ]
    images = {"observation.images.wrist": (3, 4, 6), "observation.images.top": (3, 2, 3)}
    mapper = ObservationMapper("n", inputs, images, 3, ["a.pos", "b.pos", "g.pos"])
    top = np.arange(4 * 6 * 3, dtype=np.uint8).reshape(4, 6, 3)
    latest = {
        "/top/image_raw": image_message(top),
        "/wrist/image_raw": image_message(top),
        "/arm": joints(["b", "a"], [2, 1]),
        "/gripper": joints(["g"], [7]),
    }
    observation = mapper.observation(latest.__getitem__)
    assert observation["observation.state"].tolist() == [1, 2, 7]
    assert np.array_equal(observation["observation.images.wrist"], top)
    assert observation["observation.images.top"].shape == (2, 3, 3)  # resized to the policy's size
    unnamed = ObservationMapper("n", inputs, images, 3, None)  # no names: input order
    assert unnamed.observation(latest.__getitem__)["observation.state"].tolist() == [2, 1, 7]
    latest["/gripper"] = joints([], [])
    with pytest.raises(ObservationUnavailable, match="give 2 positions, the policy expects 3"):
        unnamed.observation(latest.__getitem__)
    with pytest.raises(SettingsError, match="no Image input for policy feature observation.images.side"):
        ObservationMapper("n", inputs, {"observation.images.side": (3, 2, 2), **images}, 3)
    any_name = [TopicSettings(name="/any/topic", message_type=IMAGE)]
    single = ObservationMapper("n", any_name, {"observation.images.x": (3, 4, 6)}, None)
    assert single.image_sources == {"observation.images.x": "/any/topic"}


def test_published_joint_names_come_from_settings_then_from_the_policy():
    assert action_joint_names(["j1", "j2"], 2, ["a.pos", "b.pos"]) == ["j1", "j2"]
    assert action_joint_names([], 2, ["a.pos", "b"]) == ["a", "b"]
    with pytest.raises(SettingsError, match="joint_names has 1 names but the policy outputs 2 actions"):
        action_joint_names(["j1"], 2, None)
    with pytest.raises(SettingsError, match="the policy does not record its 2 action names; set joint_names"):
        action_joint_names([], 2, ["a.pos"])


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def test_staging_shares_immutable_files_and_commits_atomically(tmp_path):
    target = tmp_path / "dataset"
    write(target / "data" / "chunk-000" / "file-000.parquet", "data")
    write(target / "meta" / "episodes" / "chunk-000" / "file-000.parquet", "episodes")
    write(target / "meta" / "info.json", "info v1")
    write(target / "images" / "scratch.png", "scratch")
    staging = staged_directory.prepare(target)
    assert staging == tmp_path / "dataset.staging"
    data = "data/chunk-000/file-000.parquet"
    assert os.path.samefile(staging / data, target / data)
    assert os.path.samefile(
        staging / "meta/episodes/chunk-000/file-000.parquet", target / "meta/episodes/chunk-000/file-000.parquet"
    )
    assert not os.path.samefile(staging / "meta/info.json", target / "meta/info.json")
    assert not (staging / "images").exists()
    (staging / "meta" / "info.json").write_text("info v2")  # rewritten in place by LeRobot
    assert (target / "meta" / "info.json").read_text() == "info v1"
    write(staging / "images" / "left-over.png", "x")
    staged_directory.commit(target)
    assert (target / "meta" / "info.json").read_text() == "info v2"
    assert (target / data).read_text() == "data"
    assert not (target / "images").exists()
    # The replaced version stays beside it until the writer drops it, so the last episode can be re-recorded.
    assert (tmp_path / "dataset.undo" / "meta" / "info.json").read_text() == "info v1"
    staged_directory.drop_previous(target)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dataset"]


def test_recover_after_a_crash_between_renames(tmp_path):
    target = tmp_path / "dataset"
    write(tmp_path / "dataset.retired" / "meta" / "info.json", "committed")
    write(tmp_path / "dataset.staging" / "meta" / "info.json", "half-written")
    staged_directory.recover(target)
    assert (target / "meta" / "info.json").read_text() == "committed"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dataset"]
    empty = tmp_path / "empty"
    empty.mkdir()
    assert not staged_directory.prepare(empty).exists()  # LeRobot creates the dataset there
    first = tmp_path / "new"
    assert staged_directory.prepare(first) == tmp_path / "new.staging"
    write(tmp_path / "new.staging" / "meta" / "info.json", "first episode")
    staged_directory.commit(first)
    assert (first / "meta" / "info.json").read_text() == "first episode"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dataset", "empty", "new"]
