"""PPO's env steps/s on so100_reach against the floor of raw physics on every core, measured in one run.

The floor is mj_step/s of the training model's worlds rolled out by MuJoCo in C on a thread per core with
no Python between steps (reach_batch.physics_steps_per_s), divided by the physics steps of one action.
Each PPO run reports its env steps/s while collecting rollouts (the environments and the policy's
forward passes: what the vectorised environments decide) and over the whole run with its updates.
"""

import tempfile
import time
from pathlib import Path

from stable_baselines3.common.callbacks import BaseCallback

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train import envs, ppo, reach_batch

# (vec_env, n_envs) of the runs: SB3's own in this process, then the batched worlds.
RUNS = (("dummy", 4), ("batch", 16), ("batch", 32), ("batch", 64))
FLOOR_WORLDS = 64


class RolloutClock(BaseCallback):
    """Seconds spent collecting rollouts (from each rollout's start to its end)."""

    def __init__(self):
        super().__init__()
        self.seconds = 0.0
        self._since = 0.0

    def _on_rollout_start(self) -> None:
        self._since = time.perf_counter()

    def _on_rollout_end(self) -> None:
        self.seconds += time.perf_counter() - self._since

    def _on_step(self) -> bool:
        return True


def floor_env_steps_per_s() -> float:
    return reach_batch.physics_steps_per_s(FLOOR_WORLDS) / arm.STEPS_PER_ACTION


def run(vec_env: str, n_envs: int, steps: int) -> tuple[float, float]:
    """(env steps/s while collecting, env steps/s over the whole run) of PPO for `steps` steps."""
    clock = RolloutClock()
    with tempfile.TemporaryDirectory() as scratch:
        start = time.perf_counter()
        metadata = ppo.train(
            envs.REACH,
            steps,
            Path(scratch) / "ppo",
            checkpoint_every=steps,
            eval_episodes=0,
            vec_env=vec_env,
            settings=ppo.PpoSettings.for_envs(n_envs),
            progress=False,
            log=lambda text: None,
            callbacks=(clock,),
        )
        wall = time.perf_counter() - start
    return metadata["steps"] / clock.seconds, metadata["steps"] / wall


def report(steps: int) -> None:
    floor = floor_env_steps_per_s()
    print(
        f"floor: raw physics on {reach_batch.cores()} cores, {floor:.0f} env steps/s ({arm.STEPS_PER_ACTION} mj_step each)"
    )
    for vec_env, n_envs in RUNS:
        collecting, overall = run(vec_env, n_envs, steps)
        print(
            f"ppo {vec_env:>5} x{n_envs:<3}: collecting {collecting:6.0f} env steps/s = {collecting / floor:.2f}x floor; "
            f"with updates {overall:6.0f} = {overall / floor:.2f}x"
        )
