"""`so100_reach`: bring the SO-100's grasp point to a random goal in its workspace.

Observation (float32, 17): the angles of shoulder_pan, shoulder_lift, elbow_flex and wrist_flex
(rad), their velocities (/VELOCITY_SCALE), the grasp point, the goal, and goal minus grasp point
(m, world frame; the base of the arm is the origin). Action (4, in [-1, 1]): the change of each
joint's goal angle from its present angle, times MAX_DELTA_RAD, at 20 Hz (see sim/arm_task.py).
Reward: minus the grasp-to-goal distance at every step. An episode lasts MAX_EPISODE_STEPS actions
(2.5 s); it is a success when the final distance is under SUCCESS_DISTANCE_M.
Goals are the grasp points of random joint angles in GOAL_JOINT_RANGES, above the table top, so
every goal is reachable.
"""

import gymnasium as gym
import mujoco
import numpy as np

from joshua_runtime.sim import arm_task as arm

MAX_EPISODE_STEPS = 50
SUCCESS_DISTANCE_M = 0.04
# Joint angles whose grasp points are the goals (rad, ARM_JOINTS order), and the lowest goal height.
GOAL_JOINT_RANGES = np.array([(-1.0, 1.0), (-0.3, 1.2), (-1.2, 1.0), (-1.2, 1.2)])
MIN_GOAL_HEIGHT_M = 0.03
# Spread of the initial joint angles around the home pose (rad).
START_NOISE_RAD = 0.1
OBSERVATION_SIZE = 17


def sample_goal(kinematics: arm.ArmKinematics, rng: np.random.Generator) -> np.ndarray:
    """A reachable goal: the grasp point of random joint angles, above the table."""
    while True:
        point = kinematics.grasp_point(rng.uniform(GOAL_JOINT_RANGES[:, 0], GOAL_JOINT_RANGES[:, 1]))
        if point[2] >= MIN_GOAL_HEIGHT_M and point[0] > 0.05:
            return point


class So100ReachEnv(gym.Env):
    """The reach task on C MuJoCo (one world per instance)."""

    metadata = {"render_modes": []}

    def __init__(self, goal=None):
        self.model = arm.load_training_model()
        self.data = mujoco.MjData(self.model)
        self.addresses = arm.arm_addresses(self.model)
        self.kinematics = arm.ArmKinematics()
        self.fixed_goal = None if goal is None else np.asarray(goal, float)
        self.goal = np.zeros(3)
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, (OBSERVATION_SIZE,), np.float32)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (len(arm.ARM_JOINTS),), np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        mujoco.mj_resetData(self.model, self.data)
        start = self.np_random.uniform(-START_NOISE_RAD, START_NOISE_RAD, len(arm.ARM_JOINTS))
        self.data.qpos[self.addresses.qpos] = start
        self.data.ctrl[self.addresses.actuators] = start
        self.data.ctrl[self.addresses.held_actuators] = 0.0
        self.goal = self.fixed_goal if self.fixed_goal is not None else sample_goal(self.kinematics, self.np_random)
        mujoco.mj_forward(self.model, self.data)
        return self._observation(), {"distance": self._distance()}

    def step(self, action):
        positions = self.data.qpos[self.addresses.qpos]
        self.data.ctrl[self.addresses.actuators] = arm.goals_from_action(positions, action, self.addresses)
        mujoco.mj_step(self.model, self.data, nstep=arm.STEPS_PER_ACTION)
        distance = self._distance()
        info = {"distance": distance, "is_success": distance < SUCCESS_DISTANCE_M}
        return self._observation(), -distance, False, False, info

    def _grasp(self) -> np.ndarray:
        return self.data.site_xpos[self.addresses.grasp]

    def _distance(self) -> float:
        return float(np.linalg.norm(self._grasp() - self.goal))

    def _observation(self) -> np.ndarray:
        return arm.observation(
            self.data.qpos[self.addresses.qpos], self.data.qvel[self.addresses.dof], self._grasp(), self.goal
        )


# The goal an INFERENCE node serving a reach policy aims at, unless the policy's metadata says
# otherwise: in front of the arm, above the cube.
SERVING_GOAL = np.array([0.22, 0.06, 0.10])
