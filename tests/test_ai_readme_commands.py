"""Every command of the AI README (runtime/joshua_runtime/ai/README.md) works as written, offline.

Its runnable blocks run in order in one temporary working directory, with a fresh HOME, a private
model registry and the checkout's .venv/bin first on PATH (as after `source .venv/bin/activate`).
Nothing may be downloaded: the home has no cached weights and the Hugging Face Hub is offline.
"""

import os

import pytest

from testsupport.joshuac_cli import ROOT
from testsupport.readme_blocks import fresh_home, home_env, network_only_blocks, run_blocks, runnable_blocks

AI_README = ROOT / "runtime" / "joshua_runtime" / "ai" / "README.md"


def test_every_command_block_is_marked_runnable():
    text = AI_README.read_text()
    shown_only = network_only_blocks(AI_README)  # LeRobot's pretrained SmolVLA comes from the Hub
    assert text.count("```sh\n") == len(runnable_blocks(AI_README)) + len(shown_only)
    assert len(runnable_blocks(AI_README)) >= 2 and len(shown_only) <= 1


@pytest.mark.ai
@pytest.mark.process
def test_every_ai_readme_block_succeeds_offline_in_a_fresh_directory(tmp_path):
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
    )
    results = run_blocks(AI_README, work, env, login=False)
    listed = results[-1].stdout
    for name in ("reach_ppo", "reach_act", "arm_act"):
        assert name in listed and (registry / name).is_dir()
    assert "trained on so100_reach, 2048 steps, seed 0" in listed
    assert (work / "runs" / "demos" / "meta" / "info.json").is_file()
    assert "success rate" in results[0].stdout
    assert not (home / ".cache" / "torch").exists(), "a pretrained backbone was downloaded"
