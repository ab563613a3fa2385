"""Policies as `act(observation) -> action` for rollouts: saved PPO, saved LeRobot, random, zeros.

A LeRobot policy trained on recorded demonstrations does not read the task's observation vector:
it sees the six joint angles and the camera (arm_view.py) and outputs six goal angles, which are
turned back into the task's normalised action (the change from the present angles over
MAX_DELTA_RAD). It is evaluated with the goal its demonstrations reached (a fixed goal).
"""

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.ai import data_only, model_files, saved_policy
from joshua_runtime.errors import SettingsError
from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train import envs


@dataclass
class Actor:
    """What a rollout needs: the action function, a reset between episodes, options of the environment."""

    make_act: Callable  # unwrapped env -> (observation -> action)
    env_kwargs: dict = field(default_factory=dict)
    reset: Callable[[], None] | None = None
    close: Callable[[], None] = lambda: None


def random_actor() -> Actor:
    return Actor(make_act=lambda env: None)


def ppo_actor(directory: Path) -> Actor:
    from joshua_runtime.train import ppo

    model = ppo.load(directory)
    return Actor(make_act=lambda env: lambda observation: model.predict(observation, deterministic=True)[0])


def goal_actor(goal_angles: Callable[[np.ndarray, np.ndarray], np.ndarray], env_kwargs: dict) -> Actor:
    """An actor that outputs goal angles for the six SO-100 joints from (joint angles, camera image)."""
    from joshua_runtime.train.arm_view import ArmView

    views = []

    def make_act(env):
        view = ArmView(env.model, env.data)
        views.append(view)

        def act(_observation):
            state = view.state()
            goals = goal_angles(state, view.image())[: len(arm.ARM_JOINTS)]
            return np.clip((goals - state[: len(arm.ARM_JOINTS)]) / arm.MAX_DELTA_RAD, -1.0, 1.0)

        return act

    return Actor(make_act=make_act, env_kwargs=env_kwargs, close=lambda: [v.close() for v in views])


def demonstration_goal_kwargs() -> dict:
    from joshua_runtime.train.demonstrations import DEMONSTRATION_GOAL

    return {"goal": DEMONSTRATION_GOAL}


def zeros_actor() -> Actor:
    """Sends goal angle 0 to every joint: the arm goes back to its home pose (the baseline of imitation)."""

    def act(observation):
        angles = observation[: len(arm.ARM_JOINTS)]
        return np.clip(-angles / arm.MAX_DELTA_RAD, -1.0, 1.0)

    return Actor(make_act=lambda env: act, env_kwargs=demonstration_goal_kwargs())


def lerobot_actor(directory: Path) -> Actor:
    from joshua_runtime.ai import features as keys
    from joshua_runtime.ai.policy_runner import PolicyRunner

    runner = PolicyRunner(directory, "cpu")
    image_keys = list(runner.shapes.images)
    if len(image_keys) > 1 or runner.shapes.state_size not in (None, len(SO100_JOINTS)):
        raise SettingsError(f"the policy in {directory} does not read one camera and the six SO-100 joint angles")

    def goal_angles(state, image):
        observation = {keys.STATE: state}
        if image_keys:
            observation[image_keys[0]] = image
        return runner.act(observation)

    actor = goal_actor(goal_angles, demonstration_goal_kwargs())
    actor.reset = runner.reset
    return actor


def load_actor(directory: str | Path, env_id: str) -> Actor:
    """The actor of a policy saved by `joshua-train` (PPO) or by LeRobot, for environment `env_id`."""
    envs.check_env_id(env_id)
    path = Path(directory).expanduser()
    if not path.is_dir():
        raise SettingsError(f"policy directory {directory} does not exist")
    metadata = saved_policy.read(path)
    if metadata is not None and metadata["kind"] == saved_policy.KIND_PPO:
        if metadata.get("env") != env_id:
            raise SettingsError(f"the policy in {directory} was trained on {metadata.get('env')}, not {env_id}")
        data_only.check(path)
        return ppo_actor(path)
    if env_id != envs.REACH:
        raise SettingsError(
            f"LeRobot policies are evaluated on {envs.REACH} only (their demonstrations reach a fixed goal)"
        )
    policy_dir = model_files.policy_directory(path)
    data_only.check(policy_dir)
    return lerobot_actor(policy_dir)
