"""`so100_push`: push the cube across the table to a goal with the SO-100's grasp point.

Observation (float32, 23): as in `so100_reach` with the cube's centre in place of the goal
(angles, velocities, grasp point, cube, cube minus grasp point), then the goal and goal minus
cube. Action: as in `so100_reach`. Reward: minus the cube-to-goal distance on the table plane,
minus half the grasp-to-cube distance (it draws the gripper to the cube first). An episode lasts
MAX_EPISODE_STEPS actions (5 s); it is a success when the cube ends within SUCCESS_DISTANCE_M of the goal.
"""

import gymnasium as gym
import mujoco
import numpy as np

from joshua_runtime.sim import arm_task as arm

MAX_EPISODE_STEPS = 100
SUCCESS_DISTANCE_M = 0.03
CUBE_HALF_SIZE_M = 0.015
# Where the cube starts (x, y ranges, m) and how far its goal is from there.
CUBE_START = np.array([(0.16, 0.26), (-0.10, 0.10)])
GOAL_OFFSET_M = (0.05, 0.10)
START_NOISE_RAD = 0.1
OBSERVATION_SIZE = 23


class So100PushEnv(gym.Env):
    """The push task on C MuJoCo (one world per instance)."""

    metadata = {"render_modes": []}

    def __init__(self):
        self.model = arm.load_training_model()
        self.data = mujoco.MjData(self.model)
        self.addresses = arm.arm_addresses(self.model)
        cube = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, "cube")
        self.cube_qpos = self.model.jnt_qposadr[cube]
        self.cube_body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, "cube")
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
        cube_xy = self.np_random.uniform(CUBE_START[:, 0], CUBE_START[:, 1])
        self.data.qpos[self.cube_qpos : self.cube_qpos + 7] = [*cube_xy, CUBE_HALF_SIZE_M, 1, 0, 0, 0]
        angle = self.np_random.uniform(-np.pi, np.pi)
        offset = self.np_random.uniform(*GOAL_OFFSET_M)
        self.goal = np.array(
            [cube_xy[0] + offset * np.cos(angle), cube_xy[1] + offset * np.sin(angle), CUBE_HALF_SIZE_M]
        )
        mujoco.mj_forward(self.model, self.data)
        return self._observation(), {"distance": self._cube_to_goal()}

    def step(self, action):
        positions = self.data.qpos[self.addresses.qpos]
        self.data.ctrl[self.addresses.actuators] = arm.goals_from_action(positions, action, self.addresses)
        mujoco.mj_step(self.model, self.data, nstep=arm.STEPS_PER_ACTION)
        distance = self._cube_to_goal()
        reach = float(np.linalg.norm(self._cube() - self._grasp()))
        info = {"distance": distance, "is_success": distance < SUCCESS_DISTANCE_M}
        return self._observation(), -distance - 0.5 * reach, False, False, info

    def _grasp(self) -> np.ndarray:
        return self.data.site_xpos[self.addresses.grasp]

    def _cube(self) -> np.ndarray:
        return self.data.xpos[self.cube_body]

    def _cube_to_goal(self) -> float:
        return float(np.linalg.norm((self._cube() - self.goal)[:2]))

    def _observation(self) -> np.ndarray:
        reach = arm.observation(
            self.data.qpos[self.addresses.qpos], self.data.qvel[self.addresses.dof], self._grasp(), self._cube()
        )
        return np.concatenate([reach, self.goal, self.goal - self._cube()]).astype(np.float32)
