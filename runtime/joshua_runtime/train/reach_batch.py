"""`so100_reach` on many C MuJoCo worlds stepped together by MuJoCo's threaded rollout (`--vec-env batch`).

One process holds every world. Each action steps all of them STEPS_PER_ACTION physics steps in one call
of `mujoco.rollout`, spread over a thread per core, so no Python runs between physics steps and no
process boundary is crossed: stable-baselines3's DummyVecEnv steps the worlds one at a time through
gymnasium's wrappers on one core, and its SubprocVecEnv pickles every step through a pipe per world.
The task is reach_env.py's: model, observation, action, reward, goals and episode length.
"""

import os

import mujoco
import numpy as np
from mujoco import rollout

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.sim.model import model_path

STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS  # time, qpos, qvel, act, ...: what a world is between actions


def training_model_with_grasp_sensor() -> mujoco.MjModel:
    """The training model with a sensor of the grasp point's position (rollout reports sensors, not sites)."""
    spec = mujoco.MjSpec.from_file(str(model_path(arm.MODEL)))
    spec.option.timestep = arm.TRAINING_TIMESTEP_S
    spec.add_sensor(type=mujoco.mjtSensor.mjSENS_FRAMEPOS, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=arm.GRASP_SITE)
    return spec.compile()


def cores() -> int:
    return len(os.sched_getaffinity(0))


class RolloutWorlds:
    """`count` worlds of the training model as rows of a state array, stepped by mujoco.rollout on `threads`."""

    def __init__(self, count: int, threads: int | None = None):
        self.count = count
        self.model = training_model_with_grasp_sensor()
        self.addresses = arm.arm_addresses(self.model)
        self.kinematics = arm.ArmKinematics()
        self.threads = [mujoco.MjData(self.model) for _ in range(max(1, min(threads or cores(), count)))]
        self.chunk = -(-count // len(self.threads))  # one run of worlds per thread (rollout's default: ten)
        blank = mujoco.MjData(self.model)
        template = np.empty(mujoco.mj_stateSize(self.model, STATE))
        mujoco.mj_getState(self.model, blank, template, STATE)
        self.state = np.tile(template, (count, 1))
        self.template = template
        self.qpos = 1 + self.addresses.qpos  # the state starts with the time
        self.qvel = 1 + self.model.nq + self.addresses.dof
        self.control = np.zeros((count, 1, self.model.nu))
        self.grasp = np.zeros((count, 3))
        self._states = np.empty((count, arm.STEPS_PER_ACTION, template.size))
        self._sensors = np.empty((count, arm.STEPS_PER_ACTION, self.model.nsensordata))

    def reset(self, angles: np.ndarray) -> None:
        """Every world at rest at the given arm angles (count x 4), holding them."""
        self.state[:] = self.template
        self.state[:, self.qpos] = angles
        self.control[:] = 0.0
        self.control[:, 0, self.addresses.actuators] = angles
        self.grasp = np.array([self.kinematics.grasp_point(a) for a in angles])

    def step(self, actions: np.ndarray) -> None:
        goals = arm.goals_from_action(self.state[:, self.qpos], actions, self.addresses)
        self.control[:, 0, self.addresses.actuators] = goals
        rollout.rollout(
            self.model,
            self.threads,
            self.state,
            self.control,
            nstep=arm.STEPS_PER_ACTION,
            state=self._states,
            sensordata=self._sensors,
            chunk_size=self.chunk,
            persistent_pool=True,
        )
        self.state[:] = self._states[:, -1]
        self.grasp = self._sensors[:, -1, :3].copy()  # as site_xpos after mj_step: of the last step's forward pass

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(angles, velocities, grasp points) of every world."""
        return self.state[:, self.qpos].copy(), self.state[:, self.qvel].copy(), self.grasp.copy()


def physics_steps_per_s(count: int, actions: int = 50) -> float:
    """The floor: mj_step/s of `count` worlds rolled out `actions` x STEPS_PER_ACTION steps in one call, no Python
    between steps, on a thread per core."""
    import time

    worlds = RolloutWorlds(count)
    worlds.reset(np.zeros((count, len(arm.ARM_JOINTS))))
    control = np.repeat(worlds.control, actions * arm.STEPS_PER_ACTION, axis=1)
    start = time.perf_counter()
    rollout.rollout(worlds.model, worlds.threads, worlds.state, control, chunk_size=worlds.chunk, persistent_pool=True)
    return count * actions * arm.STEPS_PER_ACTION / (time.perf_counter() - start)
