"""Serve a `joshua-train rl` PPO policy of `so100_reach` with the interface of ai/policy_runner.py.

The INFERENCE node gives the joint angles it maps from its JointState inputs (`observation.state`,
picked by name: the four ARM_JOINTS). The rest of the task's observation is built here, as the
environment builds it (sim/arm_task.py): velocities by finite differences between ticks, the grasp point by
forward kinematics, and the goal from the policy's `joshua_policy.json` (`goal`, m, in the frame
of the arm's base; set when training, edit it to aim elsewhere). The action is turned into goal
angles for the ARM_JOINTS, published like any policy's action.
"""

import time
from pathlib import Path

import numpy as np

from joshua_runtime.ai import features as keys
from joshua_runtime.ai import ppo_files, saved_policy
from joshua_runtime.ai.policy_runner import PolicyShapes
from joshua_runtime.errors import SettingsError
from joshua_runtime.sim import arm_task as arm


class PpoRunner:
    """A saved PPO reach policy, ready for `act({"observation.state": angles})`."""

    kind = saved_policy.KIND_PPO

    def __init__(self, policy_dir: Path, rate_hz: float):
        metadata = saved_policy.read(policy_dir) or {}
        if metadata.get("env") != arm.REACH_ENV:
            raise SettingsError(
                f"only {arm.REACH_ENV} PPO policies can be served, {policy_dir} is for {metadata.get('env')}"
            )
        goal = metadata.get("goal")
        if not (isinstance(goal, list) and len(goal) == 3):
            raise SettingsError(f"{policy_dir / saved_policy.METADATA_FILE} has no goal [x, y, z]")
        self.goal = np.array(goal, dtype=float)
        self.model = ppo_files.load_policy(Path(policy_dir))
        self.kinematics = arm.ArmKinematics()
        self.period_s = 1.0 / rate_hz
        self.device = "cpu"
        self.shapes = PolicyShapes(images={}, state_size=len(arm.ARM_JOINTS), action_size=len(arm.ARM_JOINTS))
        self.feature_names = {
            keys.STATE: keys.position_names(list(arm.ARM_JOINTS)),
            keys.ACTION: keys.position_names(list(arm.ARM_JOINTS)),
        }
        self._previous: np.ndarray | None = None

    def reset(self) -> None:
        self._previous = None

    def act(self, observation: dict[str, np.ndarray], task: str = "") -> np.ndarray:
        """Goal angles of the arm joints; `task` is ignored (a PPO policy takes no instruction)."""
        positions = np.asarray(observation[keys.STATE], dtype=float)
        velocities = (
            np.zeros_like(positions) if self._previous is None else (positions - self._previous) / self.period_s
        )
        self._previous = positions
        vector = arm.observation(positions, velocities, self.kinematics.grasp_point(positions), self.goal)
        action, _ = self.model.predict(vector, deterministic=True)
        return arm.goals_from_action(positions, action, self.kinematics.addresses).astype(np.float32)

    def warm_up(self, task: str = "") -> float:
        """Run one step on a resting arm, then reset; its duration in seconds (`task`: none for PPO, as in act)."""
        start = time.perf_counter()
        self.act({keys.STATE: np.zeros(len(arm.ARM_JOINTS), np.float32)})
        self.reset()
        return time.perf_counter() - start
