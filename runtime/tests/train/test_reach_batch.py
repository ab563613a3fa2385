"""`--vec-env batch`: worlds stepped together by MuJoCo's threaded rollout are the reach task, step for step.

Each world follows exactly the trajectory of a So100ReachEnv given the same start and actions, and the
VecEnv over them ends every episode after MAX_EPISODE_STEPS actions as gymnasium's time limit does.
"""

import numpy as np

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train import reach_env
from joshua_runtime.train.reach_batch import RolloutWorlds

ACTIONS = 30
WORLDS = 3
# Both run the same C physics on float64; only the order of additions could differ.
TOLERANCE = 1e-9


def test_each_world_follows_the_single_environment_step_for_step():
    singles = [reach_env.So100ReachEnv() for _ in range(WORLDS)]
    for seed, env in enumerate(singles):
        env.reset(seed=seed)
    starts = np.stack([env.data.qpos[env.addresses.qpos] for env in singles])
    worlds = RolloutWorlds(WORLDS, threads=2)
    worlds.reset(starts)
    rng = np.random.default_rng(0)
    for _ in range(ACTIONS):
        actions = rng.uniform(-1, 1, (WORLDS, len(arm.ARM_JOINTS)))
        worlds.step(actions)
        for env, action in zip(singles, actions):
            env.step(action)
        angles, velocities, grasp = worlds.read()
        for row, env in enumerate(singles):
            assert np.allclose(angles[row], env.data.qpos[env.addresses.qpos], atol=TOLERANCE, rtol=0)
            assert np.allclose(velocities[row], env.data.qvel[env.addresses.dof], atol=TOLERANCE, rtol=0)
            assert np.allclose(grasp[row], env.data.site_xpos[env.addresses.grasp], atol=TOLERANCE, rtol=0)


def test_every_episode_ends_after_its_steps_with_the_terminal_observation():
    # Imported here, not at the top: stable-baselines3 imports torch (3 s), which every worker of the suite
    # would otherwise pay when it collects this module.
    from joshua_runtime.train.reach_vec_env import ReachVecEnv

    vec = ReachVecEnv(RolloutWorlds(WORLDS), seed=1)
    observations = vec.reset()
    assert observations.shape == (WORLDS, reach_env.OBSERVATION_SIZE) and observations.dtype == np.float32
    actions = np.zeros((WORLDS, len(arm.ARM_JOINTS)), np.float32)
    for step in range(1, reach_env.MAX_EPISODE_STEPS + 1):
        vec.step_async(actions)
        observations, rewards, dones, infos = vec.step_wait()
        assert np.allclose(rewards, [-info["distance"] for info in infos])
        assert list(dones) == [step == reach_env.MAX_EPISODE_STEPS] * WORLDS
    assert all(
        info["TimeLimit.truncated"] and info["terminal_observation"].shape == observations[0].shape for info in infos
    )
    assert not np.allclose(observations, np.stack([info["terminal_observation"] for info in infos]))  # new episodes
    assert vec.elapsed == 0
