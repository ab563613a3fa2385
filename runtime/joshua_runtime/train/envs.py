"""The training environments by gymnasium id, registered on import, and how to build them."""

import gymnasium as gym

from joshua_runtime.errors import SettingsError
from joshua_runtime.sim.arm_task import REACH_ENV
from joshua_runtime.train import push_env, reach_env

REACH = REACH_ENV
PUSH = "so100_push"
# id -> (entry point, episode length in actions)
ENVIRONMENTS = {
    REACH: ("joshua_runtime.train.reach_env:So100ReachEnv", reach_env.MAX_EPISODE_STEPS),
    PUSH: ("joshua_runtime.train.push_env:So100PushEnv", push_env.MAX_EPISODE_STEPS),
}

for _env_id, (_entry_point, _steps) in ENVIRONMENTS.items():
    if _env_id not in gym.registry:
        gym.register(id=_env_id, entry_point=_entry_point, max_episode_steps=_steps)


def check_env_id(env_id: str) -> str:
    if env_id not in ENVIRONMENTS:
        raise SettingsError(f"unknown environment {env_id!r} (known: {', '.join(sorted(ENVIRONMENTS))})")
    return env_id


def make(env_id: str, **kwargs) -> gym.Env:
    """A new environment (with its time limit) by id."""
    return gym.make(check_env_id(env_id), **kwargs)
