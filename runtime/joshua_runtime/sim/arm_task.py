"""The simulated SO-100 arm as a learning task sees it: joint addresses, the grasp point, observations.

One place turns joint positions, velocities and a goal into the observation vector, so that the
gymnasium environments and the INFERENCE node (which only has JointState messages) build exactly
the same vector. The grasp point (site "grasp", between the jaw tips) is found by forward
kinematics on the project's MuJoCo model.
"""

from dataclasses import dataclass

import mujoco
import numpy as np

from joshua_core.so100 import SO100_RANGES
from joshua_runtime.sim.model import load_model, site_id

MODEL = "builtin:so100"
# The gymnasium id of the reach task (train/envs.py registers it); the INFERENCE node serves its PPO policies.
REACH_ENV = "so100_reach"
GRASP_SITE = "grasp"
# The joints a task moves (the position of the grasp point depends on these; wrist_roll and the
# gripper are held at 0).
ARM_JOINTS = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex")
HELD_JOINTS = ("wrist_roll", "gripper")
# Physics step of the training model (coarser than the robot's 2 ms: implicitfast stays stable) and
# physics steps per action: actions at 20 Hz.
TRAINING_TIMESTEP_S = 0.005
STEPS_PER_ACTION = 10
CONTROL_PERIOD_S = TRAINING_TIMESTEP_S * STEPS_PER_ACTION
# Largest goal change per action, in rad (an action of +-1 moves the goal this far from the present angle).
MAX_DELTA_RAD = 0.15
# Scale of joint velocities in the observation (rad/s) so that every entry is of order 1.
VELOCITY_SCALE = 5.0


@dataclass(frozen=True)
class ArmAddresses:
    """MuJoCo addresses of the task joints, their actuators and the grasp site."""

    qpos: np.ndarray
    dof: np.ndarray
    actuators: np.ndarray
    held_actuators: np.ndarray
    low: np.ndarray
    high: np.ndarray
    grasp: int


def arm_addresses(model: mujoco.MjModel) -> ArmAddresses:
    def joint(name):
        return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)

    def actuator(name):
        return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, name)

    grasp = site_id(model, GRASP_SITE)
    if grasp < 0:
        raise ValueError(f"the model has no site {GRASP_SITE!r}")
    return ArmAddresses(
        qpos=np.array([model.jnt_qposadr[joint(n)] for n in ARM_JOINTS]),
        dof=np.array([model.jnt_dofadr[joint(n)] for n in ARM_JOINTS]),
        actuators=np.array([actuator(n) for n in ARM_JOINTS]),
        held_actuators=np.array([actuator(n) for n in HELD_JOINTS]),
        low=np.array([SO100_RANGES[n][0] for n in ARM_JOINTS]),
        high=np.array([SO100_RANGES[n][1] for n in ARM_JOINTS]),
        grasp=grasp,
    )


def load_training_model() -> mujoco.MjModel:
    return load_model(MODEL, timestep_s=TRAINING_TIMESTEP_S)


def goals_from_action(positions: np.ndarray, action: np.ndarray, addresses: ArmAddresses) -> np.ndarray:
    """Goal angles for a normalised action: the present angles moved by up to MAX_DELTA_RAD, clamped to range."""
    delta = np.clip(np.asarray(action, dtype=float), -1.0, 1.0) * MAX_DELTA_RAD
    return np.clip(positions + delta, addresses.low, addresses.high)


def observation(positions, velocities, grasp, *goals) -> np.ndarray:
    """Joint angles, scaled velocities, grasp point, then each goal point and its offset from the grasp point;
    of one world, or of a batch (one row per world)."""
    grasp = np.asarray(grasp, float)
    parts = [np.asarray(positions, float), np.asarray(velocities, float) / VELOCITY_SCALE, grasp]
    for goal in goals:
        goal = np.asarray(goal, float)
        parts += [goal, goal - grasp]
    return np.concatenate(parts, axis=-1).astype(np.float32)


class ArmKinematics:
    """Forward kinematics of the grasp point for given joint angles (a private MjData, no stepping)."""

    def __init__(self):
        self.model = load_training_model()
        self.data = mujoco.MjData(self.model)
        self.addresses = arm_addresses(self.model)

    def grasp_point(self, positions) -> np.ndarray:
        self.data.qpos[self.addresses.qpos] = positions
        mujoco.mj_kinematics(self.model, self.data)
        return self.data.site_xpos[self.addresses.grasp].copy()
