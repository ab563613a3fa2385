"""Every command of the AI README (runtime/joshua_runtime/ai/README.md) works as written, offline.

Its runnable blocks run in order in one temporary working directory, with a fresh HOME, a private
model registry and the checkout's .venv/bin first on PATH (as after `source .venv/bin/activate`).
Nothing may be downloaded: the home has no cached weights and the Hugging Face Hub is offline. The robots
its walk runs (recording through a recorder, serving through an INFERENCE node) join a ROS domain of their own.
"""

import json
import os

import pytest

from testsupport.joshuac_cli import ROOT
from testsupport.readme_blocks import fresh_home, home_env, network_only_blocks, run_blocks, runnable_blocks

AI_README = ROOT / "runtime" / "joshua_runtime" / "ai" / "README.md"
# The walk trains PPO and ACT, records and serves: 150-300 s on a busy 2-core machine, beyond the suite's 300 s
# default; each block still has its own BLOCK_TIMEOUT_S.
WALK_TIMEOUT_S = 900


def test_every_command_block_is_marked_runnable():
    text = AI_README.read_text()
    shown_only = network_only_blocks(AI_README)  # LeRobot's pretrained SmolVLA comes from the Hub
    assert text.count("```sh\n") == len(runnable_blocks(AI_README)) + len(shown_only)
    assert len(runnable_blocks(AI_README)) >= 2 and len(shown_only) <= 1


@pytest.mark.ai
@pytest.mark.process
@pytest.mark.timeout(WALK_TIMEOUT_S)
def test_every_ai_readme_block_succeeds_offline_in_a_fresh_directory(tmp_path, ros_env):
    home = fresh_home(tmp_path)
    work = tmp_path / "work"
    work.mkdir()
    registry = tmp_path / "registry"
    env = home_env(
        home,
        PATH=f"{ROOT / '.venv' / 'bin'}:{os.environ['PATH']}",
        JOSHUA_MODEL_REGISTRY=str(registry),
        HF_HUB_OFFLINE="1",
        XDG_CACHE_HOME=str(home / ".cache"),
        ROS_DOMAIN_ID=ros_env["ROS_DOMAIN_ID"],
        ROS_AUTOMATIC_DISCOVERY_RANGE=ros_env["ROS_AUTOMATIC_DISCOVERY_RANGE"],
    )
    results = run_blocks(AI_README, work, env, login=False)
    listed = results[-1].stdout
    for name in ("reach_ppo", "reach_act", "arm_act", "my_task_act"):
        assert name in listed and (registry / name).is_dir()
    assert "trained on so100_reach, 2048 steps, seed 0" in listed
    assert (work / "runs" / "demos" / "meta" / "info.json").is_file()
    assert "success rate" in results[0].stdout
    assert not (home / ".cache" / "torch").exists(), "a pretrained backbone was downloaded"
    assert_the_walk_recorded_trained_and_served(work, results)


def assert_the_walk_recorded_trained_and_served(work, results):
    """The walk's two episodes came through the running robot's recorder at 320x240, and the policy
    trained on one of them was served by the second robot (one of its action chunks printed)."""
    info = json.loads((work / "data" / "my_task" / "meta" / "info.json").read_text())
    assert info["total_episodes"] == 2
    assert info["features"]["observation.images.camera"]["shape"] == [240, 320, 3]
    recorded = next(result.stdout for result in results if "joshua-dataset info" in result.args[-1])
    assert "saved episode 1" in recorded and "task: wave over the cube" in recorded
    assert (work / "runs" / "my_act.png").stat().st_size > 0
    served = next(result.stdout for result in results if "registry:my_task_act" in result.args[-1])
    assert "joint_names:" in served and "time_from_start:" in served
