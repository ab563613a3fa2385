"""Scripted demonstrations of `so100_reach` in simulation, recorded as DATA_SUBSCRIBER records a robot.

The scripted arm moves from a random start near home to DEMONSTRATION_POSE (the "over the cube"
pose of sim/scripted_motion.py) with a proportional joint-space controller and some action noise.
Every control step becomes one frame of a LeRobotDataset v3.0 written by the recorder's own
FrameSampler and EpisodeWriter: the joint states (`observation.state`), the camera image
(`observation.images.camera`, stored as images) and the goal angles sent (`action`), at 20 fps.
A policy trained on it is evaluated on `so100_reach` with DEMONSTRATION_GOAL as the fixed goal.
"""

from pathlib import Path

import numpy as np

from joshua_core.message_types import IMAGE_TYPES
from joshua_core.settings import TopicSettings
from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.episode_writer import EpisodeWriter
from joshua_runtime.ai.frame_sampler import FrameSampler
from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.sim import arm_task as arm
from joshua_runtime.sim.scripted_motion import KEYFRAMES
from joshua_runtime.train import reach_env
from joshua_runtime.train.arm_view import ACTION_TOPIC, CAMERA_TOPIC, STATE_TOPIC, ArmView

DEMONSTRATION_POSE = np.array(KEYFRAMES[0][1][: len(arm.ARM_JOINTS)])
DEMONSTRATION_GOAL = arm.ArmKinematics().grasp_point(DEMONSTRATION_POSE)
IMAGE = IMAGE_TYPES[0]
FPS = round(1.0 / arm.CONTROL_PERIOD_S)
ACTION_NOISE = 0.2
TASK = "reach over the cube"
ROBOT_TYPE = "so100"


def scripted_action(positions: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Head for DEMONSTRATION_POSE at full speed, with Gaussian noise on the normalised action."""
    action = (DEMONSTRATION_POSE - positions) / arm.MAX_DELTA_RAD + rng.normal(0.0, ACTION_NOISE, len(positions))
    return np.clip(action, -1.0, 1.0)


class _Log:
    def __init__(self, echo):
        self.echo = echo

    def info(self, text, **_):
        self.echo(text)

    warning = info


def record(output: Path, episodes: int, seed: int = 0, echo=print) -> Path:
    """Record `episodes` scripted episodes into the dataset at `output` (appended to when it exists)."""
    if episodes < 1:
        raise SettingsError(f"--episodes must be positive, got {episodes}")
    output = Path(output).expanduser()
    if output.exists() and not (output / "meta" / "info.json").is_file():
        raise SettingsError(f"output {output} exists and is not a LeRobot dataset; choose another directory")
    inputs = [
        TopicSettings(name=STATE_TOPIC, message_type=keys.JOINT_STATE),
        TopicSettings(name=CAMERA_TOPIC, message_type=IMAGE),
    ]
    sampler = FrameSampler(ACTION_TOPIC, inputs, use_videos=False)
    writer = EpisodeWriter(str(output), FPS, ROBOT_TYPE, use_videos=False, log=_Log(echo))
    env = reach_env.So100ReachEnv(goal=DEMONSTRATION_GOAL)
    view = ArmView(env.model, env.data)
    rng = np.random.default_rng(seed)
    try:
        for episode in range(episodes):
            env.reset(seed=seed + episode)
            writer.start_episode(TASK)
            for _ in range(reach_env.MAX_EPISODE_STEPS):
                positions = env.data.qpos[env.addresses.qpos].copy()
                action = scripted_action(positions, rng)
                goals = np.zeros(len(SO100_JOINTS))
                goals[: len(arm.ARM_JOINTS)] = arm.goals_from_action(positions, action, env.addresses)
                messages = {
                    STATE_TOPIC: joint_state(list(SO100_JOINTS), view.state()),
                    ACTION_TOPIC: joint_state(list(SO100_JOINTS), goals),
                    CAMERA_TOPIC: rgb_to_image(view.image()),
                }
                frame = sampler.frame(messages.__getitem__)
                if episode == 0 and writer.saved_episodes == 0:
                    writer.configure(sampler.features)
                writer.add_frame(frame)
                env.step(action)
            writer.end_episode()
    finally:
        writer.close()
        view.close()
    if writer.error is not None:
        raise JoshuaError(str(writer.error))
    return output
