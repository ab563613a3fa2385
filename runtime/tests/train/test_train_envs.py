"""The gymnasium tasks on the project's MuJoCo model: spaces, goals, rewards, success, registration."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from joshua_runtime.errors import SettingsError
from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train import envs, push_env, reach_env


@pytest.mark.parametrize("env_id", sorted(envs.ENVIRONMENTS))
def test_environments_pass_gymnasiums_checks_and_are_registered_by_id(env_id):
    env = gym.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.spec.max_episode_steps == envs.ENVIRONMENTS[env_id][1]
    observation, _ = env.reset(seed=3)
    again, _ = env.reset(seed=3)
    np.testing.assert_array_equal(observation, again)


def test_reach_observation_is_angles_velocities_grasp_goal_and_offset():
    env = reach_env.So100ReachEnv()
    observation, info = env.reset(seed=1)
    angles, velocities, grasp, goal, offset = np.split(observation, [4, 8, 11, 14])
    np.testing.assert_allclose(grasp, arm.ArmKinematics().grasp_point(angles), atol=1e-5)
    np.testing.assert_allclose(offset, goal - grasp, atol=1e-5)
    assert info["distance"] == pytest.approx(np.linalg.norm(offset), abs=1e-5)
    assert goal[2] >= reach_env.MIN_GOAL_HEIGHT_M


def test_driving_the_joints_to_the_goal_pose_succeeds_and_earns_more_than_standing_still():
    """A goal made from known angles: heading for them reaches it, doing nothing does not."""
    pose = np.array([0.5, 0.6, -0.3, 0.4])
    goal = arm.ArmKinematics().grasp_point(pose)
    returns = {}
    for name in ("scripted", "still"):
        env = gym.make("so100_reach", goal=goal)
        observation, _ = env.reset(seed=0)
        total, done = 0.0, False
        while not done:
            action = (pose - observation[:4]) / arm.MAX_DELTA_RAD if name == "scripted" else np.zeros(4)
            observation, reward, terminated, truncated, info = env.step(np.clip(action, -1, 1))
            total += reward
            done = terminated or truncated
        returns[name] = (total, info["is_success"], info["distance"])
    assert returns["scripted"][1] and returns["scripted"][2] < 0.01
    assert not returns["still"][1]
    assert returns["scripted"][0] > returns["still"][0]


def test_push_rewards_moving_the_cube_to_its_goal():
    env = push_env.So100PushEnv()
    observation, info = env.reset(seed=2)
    cube, goal = observation[11:14], observation[17:20]
    assert cube[2] == pytest.approx(push_env.CUBE_HALF_SIZE_M, abs=1e-3)
    assert info["distance"] == pytest.approx(np.linalg.norm((goal - cube)[:2]), abs=1e-5)
    _, reward, *_ = env.step(np.zeros(4))
    assert reward < -info["distance"] + 1e-3


def test_unknown_environment_is_a_settings_error_naming_the_known_ones():
    with pytest.raises(SettingsError, match=r"unknown environment 'so100_fly' \(known: so100_push, so100_reach\)"):
        envs.make("so100_fly")
