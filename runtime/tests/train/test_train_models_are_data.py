"""PPO policies are weights and JSON: evaluating or resuming never unpickles, and old pickles convert only when trusted.

The crafted policy.zip (testsupport/crafted_models.py) writes a marker file when stable-baselines3's
PPO.load unpickles it; the marker must never appear.
"""

import json
import os
import subprocess
import sys

import numpy as np

from joshua_runtime.ai import saved_policy
from testsupport import crafted_models

TOOL_TIMEOUT_S = 240


def run(*args, env=None):
    return subprocess.run(
        [sys.executable, "-m", *args],
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
        timeout=TOOL_TIMEOUT_S,
    )


def test_evaluate_refuses_a_pickled_policy_and_names_the_file(tmp_path):
    marker = tmp_path / "unpickled"
    policy = crafted_models.pickled_ppo_run(tmp_path / "run", marker)
    result = run("joshua_runtime.train.cli", "evaluate", str(policy), "--env", "so100_reach", "--episodes", "1")
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith(f"joshua-train: error: {policy / 'policy.zip'} ") and "pickle" in result.stderr
    assert len(result.stderr.splitlines()) == 1 and not marker.exists()


def test_training_refuses_to_resume_from_a_pickled_checkpoint(tmp_path):
    marker = tmp_path / "unpickled"
    output = tmp_path / "run"
    output.mkdir()
    saved_policy.write(output, crafted_models.ppo_metadata(steps=0))
    checkpoint = crafted_models.sb3_zip(output / "checkpoints" / "ppo_512_steps.zip", marker)
    result = run(
        "joshua_runtime.train.cli",
        *("rl", "--env", "so100_reach", "--steps", "1024", "--output", str(output), "--no-progress"),
    )
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith(f"joshua-train: error: {checkpoint} ") and "pickle" in result.stderr
    assert not marker.exists()


def test_a_trained_ppo_policy_loads_and_acts_without_unpickling(trained_reach, monkeypatch):
    from joshua_runtime.train import envs, ppo

    output, _ = trained_reach
    env = envs.make("so100_reach")
    observation, _ = env.reset(seed=3)
    env.close()
    crafted_models.forbid_unpickling(monkeypatch)
    action = ppo.load(output).predict(observation, deterministic=True)[0]
    assert action.shape == env.action_space.shape and np.all(np.abs(action) <= 1.0)


def test_an_earlier_pickled_run_converts_only_with_trust_pickle(tmp_path):
    """An old `joshua-train rl` output (stable-baselines3's zip) becomes weights and JSON that act the same."""
    from stable_baselines3 import PPO

    from joshua_runtime.train import envs, ppo

    old = tmp_path / "old"
    old.mkdir()
    env = envs.make("so100_reach")
    model = PPO("MlpPolicy", env, policy_kwargs={"net_arch": [64, 64]}, seed=5, device="cpu")
    model.save(old / "policy.zip")
    saved_policy.write(old, crafted_models.ppo_metadata(steps=0))
    registry_env = {"JOSHUA_MODEL_REGISTRY": str(tmp_path / "registry")}

    refused = run("joshua_runtime.ai.registry_cli", "import", str(old), "--name", "old", env=registry_env)
    assert refused.returncode == 1
    assert (
        refused.stderr.startswith(f"joshua-registry: error: {old / 'policy.zip'} ")
        and "--trust-pickle" in refused.stderr
    )

    converted = run(
        "joshua_runtime.ai.registry_cli", "import", str(old), "--name", "old", "--trust-pickle", env=registry_env
    )
    assert converted.returncode == 0, converted.stderr
    entry = converted.stdout.strip().rsplit(" -> ", 1)[1]
    assert sorted(os.listdir(entry)) == ["joshua_model.json", "joshua_policy.json", "policy.safetensors"]
    assert json.loads((old / "joshua_policy.json").read_text()) == crafted_models.ppo_metadata(steps=0)  # untouched

    served = ppo.load(entry)
    observations, _ = env.reset(seed=1)
    for _ in range(20):
        expected = model.predict(observations, deterministic=True)[0]
        assert np.array_equal(served.predict(observations, deterministic=True)[0], expected)
        observations, *_ = env.step(expected)
    env.close()
