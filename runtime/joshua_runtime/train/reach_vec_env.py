"""`so100_reach` as a stable-baselines3 VecEnv over a batch of worlds that step together (C MuJoCo's threaded
rollout, reach_batch.py, or MJX, mjx_reach.py); all worlds start and end their episodes together.

Worlds offer reset(angles), step(actions) and read() -> (angles, velocities, grasp points), one row per
world; goals, start angles, observations and rewards are reach_env.py's, computed for the whole batch.
"""

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import VecEnv

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train import reach_env


class ReachVecEnv(VecEnv):
    def __init__(self, worlds, seed: int = 0):
        self.worlds = worlds
        self.kinematics = arm.ArmKinematics()
        self.rng = np.random.default_rng(seed)
        self.goals = np.zeros((worlds.count, 3))
        self.elapsed = 0
        self._actions = None
        self.render_mode = None
        observation_space = gym.spaces.Box(-np.inf, np.inf, (reach_env.OBSERVATION_SIZE,), np.float32)
        action_space = gym.spaces.Box(-1.0, 1.0, (len(arm.ARM_JOINTS),), np.float32)
        super().__init__(worlds.count, observation_space, action_space)

    def reset(self):
        noise = reach_env.START_NOISE_RAD
        self.worlds.reset(self.rng.uniform(-noise, noise, (self.num_envs, len(arm.ARM_JOINTS))))
        self.goals = np.array([reach_env.sample_goal(self.kinematics, self.rng) for _ in range(self.num_envs)])
        self.elapsed = 0
        return self._observations()[0]

    def _observations(self):
        angles, velocities, grasp = self.worlds.read()
        return arm.observation(angles, velocities, grasp, self.goals), np.linalg.norm(grasp - self.goals, axis=1)

    def step_async(self, actions) -> None:
        self._actions = actions

    def step_wait(self):
        self.worlds.step(self._actions)
        self.elapsed += 1
        observations, distances = self._observations()
        done = self.elapsed >= reach_env.MAX_EPISODE_STEPS
        infos = [{"distance": float(d), "is_success": bool(d < reach_env.SUCCESS_DISTANCE_M)} for d in distances]
        if done:
            for info, observation in zip(infos, observations):
                info["terminal_observation"] = observation
                info["TimeLimit.truncated"] = True
            observations = self.reset()
        return observations, -distances.astype(np.float32), np.full(self.num_envs, done), infos

    def close(self) -> None:
        pass

    def get_attr(self, attr_name, indices=None):
        return [getattr(self, attr_name)] * len(self._get_indices(indices))

    def set_attr(self, attr_name, value, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name, *method_args, indices=None, **method_kwargs):
        raise NotImplementedError(f"{method_name} is not available on a batch of worlds")

    def env_is_wrapped(self, wrapper_class, indices=None):
        return [False] * len(self._get_indices(indices))
