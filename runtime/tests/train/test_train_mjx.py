"""MuJoCo-XLA and C MuJoCo agree on the reach task's variant model for a few actions (on the CPU).

The first MJX step compiles (tens of seconds on a CPU); the worlds are the arm alone, without
contacts or constraints (mjx_reach.variant_model), which keeps that compilation short.
"""

import mujoco
import numpy as np

from joshua_runtime.sim import arm_task as arm

ACTIONS = 4
START = np.array([0.1, -0.2, 0.3, 0.2])
# Float32 on jax against float64 in C, over 40 physics steps.
ANGLE_TOLERANCE_RAD = 2e-3
GRASP_TOLERANCE_M = 1e-3


def test_mjx_steps_match_c_mujoco_within_tolerance():
    from joshua_runtime.train import mjx_reach  # jax: a second and more, paid only by this test

    worlds = mjx_reach.MjxWorlds(2)
    worlds.reset(np.stack([START, -START]))
    model = worlds.model
    data = [mujoco.MjData(model) for _ in range(2)]
    for sign, world in zip((1, -1), data):
        world.qpos[worlds.addresses.qpos] = sign * START
        world.ctrl[worlds.addresses.actuators] = sign * START
        mujoco.mj_forward(model, world)
    rng = np.random.default_rng(0)
    for _ in range(ACTIONS):
        actions = rng.uniform(-1, 1, (2, len(arm.ARM_JOINTS))).astype(np.float32)
        worlds.step(actions)
        for world, action in zip(data, actions):
            positions = world.qpos[worlds.addresses.qpos]
            world.ctrl[worlds.addresses.actuators] = arm.goals_from_action(positions, action, worlds.addresses)
            mujoco.mj_step(model, world, nstep=arm.STEPS_PER_ACTION)
    angles, _, grasp = worlds.read()
    expected_angles = np.stack([world.qpos[worlds.addresses.qpos] for world in data])
    expected_grasp = np.stack([world.site_xpos[worlds.addresses.grasp] for world in data])
    assert np.abs(expected_angles - START).max() > 0.1  # the arm really moved
    np.testing.assert_allclose(angles, expected_angles, atol=ANGLE_TOLERANCE_RAD)
    np.testing.assert_allclose(grasp, expected_grasp, atol=GRASP_TOLERANCE_M)
