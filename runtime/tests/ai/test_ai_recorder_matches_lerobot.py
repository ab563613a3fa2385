"""A recording is what LeRobot's own writer makes of the same frames: LeRobot stays the judge of the format.

The recorder (its writer in a process of its own) records an episode of the synthetic arm; then this
test hands the recorded frames, read back, to LeRobotDataset.create / add_frame / save_episode /
finalize itself, and compares the two datasets: info.json, every data column, the images' pixels,
the tasks and the episode metadata.
"""

import json
import signal

import numpy as np
import pyarrow.parquet as pq
from ai_support import NodeProcess
from test_ai_recorder import Sensors, load, record_one, recorder_settings

DEFAULT_FEATURES = ("timestamp", "frame_index", "episode_index", "index", "task_index")
DATA_COLUMNS = ("action", "observation.state", *DEFAULT_FEATURES)
EPISODE_COLUMNS = ("episode_index", "tasks", "length", "dataset_from_index", "dataset_to_index")
CAMERA = "observation.images.rec_camera"


def frames_of(dataset) -> list[dict]:
    """The frames as add_frame takes them: arrays in the features' shapes (images HWC uint8)."""
    frames = []
    for i in range(len(dataset)):
        item = dataset[i]
        frames.append(
            {
                "action": item["action"].numpy(),
                "observation.state": item["observation.state"].numpy(),
                CAMERA: (item[CAMERA].permute(1, 2, 0).numpy() * 255).round().astype(np.uint8),
                "task": item["task"],
            }
        )
    return frames


def lerobot_writes(recorded, root) -> None:
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    features = {k: v for k, v in recorded.meta.features.items() if k not in DEFAULT_FEATURES}
    reference = LeRobotDataset.create(
        "local/reference", recorded.meta.fps, features, root=root, robot_type=recorded.meta.robot_type, use_videos=False
    )
    for frame in frames_of(recorded):
        reference.add_frame(frame)
    reference.save_episode()
    reference.finalize()


def table(root, pattern: str, columns) -> dict:
    [path] = sorted(root.glob(pattern))
    return pq.read_table(path, columns=list(columns)).to_pydict()


def test_a_recording_equals_lerobots_own_writing_of_its_frames(tmp_path, ai_env, ros_peer, lerobot_offline):
    output, reference = tmp_path / "recorded", tmp_path / "reference"
    Sensors(ros_peer)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)
    try:
        record_one(node, 0)
        assert node.stop(signal.SIGINT) == 0, node.output
    finally:
        node.kill()
    recorded = load(output)
    assert recorded.meta.total_episodes == 1 and len(recorded) > 0
    lerobot_writes(recorded, reference)

    assert json.loads((output / "meta/info.json").read_text()) == json.loads((reference / "meta/info.json").read_text())
    ours, theirs = (table(root, "data/*/*.parquet", DATA_COLUMNS) for root in (output, reference))
    assert ours == theirs
    assert table(output, "meta/tasks.parquet", ["task_index"]) == table(reference, "meta/tasks.parquet", ["task_index"])
    ours_episodes, their_episodes = (
        table(root, "meta/episodes/*/*.parquet", EPISODE_COLUMNS) for root in (output, reference)
    )
    assert ours_episodes == their_episodes
    written = load(reference)
    for i in range(len(recorded)):
        assert np.array_equal(recorded[i][CAMERA].numpy(), written[i][CAMERA].numpy()), i
