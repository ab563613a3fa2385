"""A real ACT trained offline in seconds: a 320x240 camera, a 6-joint state, chunks of CHUNK_SIZE actions.

The dataset is written by the recorder's own FrameSampler and EpisodeWriter (LeRobotDataset v3.0):
a few short episodes in which the arm sweeps and the camera sees a pattern move with it; the policy is
trained by `joshua-train imitation`'s code (LeRobot's training loop, no pretrained backbone, nothing
downloaded) for a few steps. The point is not a good policy but a real one, with LeRobot's ResNet-18 backbone on a real 320x240 input, whose call takes longer than several control periods on
a CPU. Used by the chunked-inference tests and bench/remote_inference.py.
"""

from pathlib import Path

import numpy as np

from joshua_core import so100
from joshua_core.settings import TopicSettings

WIDTH, HEIGHT = 320, 240
CHUNK_SIZE = 100  # ACT's default: 3.3 s of actions at 30 Hz
FPS = 30
EPISODES, FRAMES_PER_EPISODE = 2, 40
TASK = "follow the bar"
TRAINING_STEPS, BATCH_SIZE = 3, 2
JOINTS = list(so100.SO100_JOINTS)
CAMERA_TOPIC, STATE_TOPIC, ACTION_TOPIC = "/camera/image_raw", "/follower/joint_states", "/leader/joint_states"


def pose(t: float) -> np.ndarray:
    """The demonstrated pose at time t (s): every joint sweeping slowly, out of phase."""
    return 0.4 * np.sin(0.8 * t + np.arange(len(JOINTS)))


def frame_image(t: float, width: int = WIDTH, height: int = HEIGHT) -> np.ndarray:
    """An RGB picture of the moment (320x240 by default): a bar whose position follows the first joint."""
    image = np.zeros((height, width, 3), np.uint8)
    image[:, :, 2] = np.linspace(40, 200, width, dtype=np.uint8)
    bar = max(width // 16, 2)
    column = int((pose(t)[0] + 0.5) * (width - bar))
    image[:, column : column + bar, 0] = 255
    return image


def record_dataset(
    output: Path,
    episodes: int = EPISODES,
    frames: int = FRAMES_PER_EPISODE,
    size: tuple[int, int] = (WIDTH, HEIGHT),
    use_videos: bool = False,
    tasks: tuple[str, ...] = (TASK,),
) -> Path:
    """A LeRobot dataset of `episodes` demonstrations of `frames` frames at FPS, images of `size` (width,
    height) stored as PNG or, with `use_videos`, as AV1 video as DATA_SUBSCRIBER records them; episode i
    has task tasks[i % len(tasks)]."""
    from joshua_runtime.ai import features as keys
    from joshua_runtime.ai.episode_writer import EpisodeWriter
    from joshua_runtime.ai.frame_sampler import FrameSampler
    from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

    inputs = [
        TopicSettings(name=STATE_TOPIC, message_type=keys.JOINT_STATE),
        TopicSettings(name=CAMERA_TOPIC, message_type=keys.IMAGE_TYPES[0]),
    ]
    sampler = FrameSampler(ACTION_TOPIC, inputs, use_videos=use_videos)
    writer = EpisodeWriter(str(output), FPS, "so100", use_videos=use_videos, log=_QuietLog())
    try:
        for episode in range(episodes):
            writer.start_episode(tasks[episode % len(tasks)])
            for step in range(frames):
                t = episode * 10.0 + step / FPS
                messages = {
                    STATE_TOPIC: joint_state(JOINTS, pose(t)),
                    ACTION_TOPIC: joint_state(JOINTS, pose(t + 1 / FPS)),
                    CAMERA_TOPIC: rgb_to_image(frame_image(t, *size)),
                }
                frame = sampler.frame(messages.__getitem__)
                if episode == 0 and step == 0:
                    writer.configure(sampler.features)
                writer.add_frame(frame)
            writer.end_episode()
    finally:
        writer.close()
    if writer.error is not None:
        raise RuntimeError(f"recording the tiny dataset failed: {writer.error}")
    return output


def train_tiny_act(workdir: Path, chunk_size: int = CHUNK_SIZE) -> Path:
    """Record the dataset and train the ACT in `workdir`; the saved policy directory."""
    from joshua_runtime.train import imitation

    dataset = record_dataset(Path(workdir) / "dataset")
    options = imitation.TrainingOptions(
        batch_size=BATCH_SIZE, device="cpu", workers=0, sizes={"chunk_size": chunk_size, "n_action_steps": 1}
    )
    return imitation.train(dataset, "act", TRAINING_STEPS, Path(workdir) / "act", options)


class _QuietLog:
    def info(self, *_args, **_kwargs) -> None:
        pass

    def warning(self, message, **_kwargs) -> None:
        print(message)
