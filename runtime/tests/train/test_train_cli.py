"""`joshua-train` as a user runs it: PPO with checkpoints and resumption, evaluation, registry lineage, bad input."""

import json
import os
import subprocess
import sys

import pytest

from joshua_runtime.ai import data_only, saved_policy

TOOL_TIMEOUT_S = 240
STEPS = 1024  # one PPO update of 4 environments x 256 steps


def run(*args, registry=None, check=True, temporary=None):
    env = dict(os.environ)
    if registry is not None:
        env["JOSHUA_MODEL_REGISTRY"] = str(registry)
    if temporary is not None:
        env["TMPDIR"] = str(temporary)
    result = subprocess.run(
        [sys.executable, "-m", *args], capture_output=True, text=True, env=env, timeout=TOOL_TIMEOUT_S
    )
    if check:
        assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    return result


def train(output, steps, temporary=None):
    return run(
        "joshua_runtime.train.cli",
        "rl",
        "--env",
        "so100_reach",
        "--steps",
        str(steps),
        "--output",
        str(output),
        "--seed",
        "3",
        "--checkpoint-every",
        "512",
        "--eval-episodes",
        "2",
        "--no-progress",
        temporary=temporary,
    )


def test_rl_checkpoints_resumes_and_is_imported_with_its_lineage(tmp_path):
    output = tmp_path / "run"
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    first = train(output, STEPS, temporary)
    assert not list(temporary.glob("SB3-*"))  # stable-baselines3's default logger made one at every run
    assert "saved PPO policy for so100_reach after 1024 steps" in first.stdout
    assert sorted(p.name for p in (output / "checkpoints").iterdir()) == [
        "ppo_1024_steps.safetensors",
        "ppo_512_steps.safetensors",
    ]
    assert sorted(p.name for p in output.iterdir()) == ["checkpoints", "joshua_policy.json", "policy.safetensors"]
    data_only.check(output)  # weights and JSON: no file of the run is a pickle
    metadata = saved_policy.read(output)
    assert metadata["kind"] == "sb3-ppo" and metadata["env"] == "so100_reach"
    assert metadata["steps"] == STEPS and metadata["seed"] == 3 and metadata["evaluation"]["episodes"] == 2

    second = train(output, 2 * STEPS)
    assert f"continuing so100_reach from {output / 'checkpoints' / 'ppo_1024_steps.safetensors'} (1024 steps)" in (
        second.stdout
    )
    assert saved_policy.read(output)["steps"] == 2 * STEPS
    assert (output / "checkpoints" / "ppo_2048_steps.safetensors").is_file()

    evaluated = run(
        "joshua_runtime.train.cli", "evaluate", str(output), "--env", "so100_reach", "--episodes", "3", "--json"
    )
    result = json.loads(evaluated.stdout)
    assert set(result) == {"success_rate", "mean_return", "episodes"} and result["episodes"] == 3

    registry = tmp_path / "registry"
    imported = run("joshua_runtime.ai.registry_cli", "import", str(output), "--name", "reach", registry=registry)
    entry_dir = imported.stdout.strip().rsplit(" -> ", 1)[1]
    assert sorted(os.listdir(entry_dir)) == ["joshua_model.json", "joshua_policy.json", "policy.safetensors"]
    listed = run("joshua_runtime.ai.registry_cli", "list", registry=registry).stdout
    assert "sb3-ppo" in listed
    assert "trained on so100_reach, 2048 steps, seed 3, success" in listed


def test_random_baseline_prints_the_three_fields():
    result = run("joshua_runtime.train.cli", "evaluate", "--random", "--env", "so100_push", "--episodes", "2", "--json")
    assert json.loads(result.stdout) == {**json.loads(result.stdout), "episodes": 2}
    assert result.stdout.count("\n") == 1


@pytest.mark.parametrize(
    "args, code, message",
    [
        (
            ["rl", "--env", "so100_fly", "--steps", "10", "--output", "{tmp}/x"],
            2,
            "joshua-train: error: unknown environment 'so100_fly' (known: so100_push, so100_reach)",
        ),
        (
            ["rl", "--env", "so100_reach", "--steps", "10", "--output", "{tmp}/full"],
            2,
            "joshua-train: error: output {tmp}/full is not empty and holds no joshua-train run; choose another directory",
        ),
        (
            ["rl", "--env", "so100_push", "--steps", "10", "--vec-env", "batch", "--output", "{tmp}/push"],
            2,
            "joshua-train: error: --vec-env batch runs so100_reach only",
        ),
        (
            ["evaluate", "{tmp}/missing", "--env", "so100_reach", "--episodes", "2"],
            2,
            "joshua-train: error: policy directory {tmp}/missing does not exist",
        ),
        (
            ["evaluate", "--env", "so100_reach", "--episodes", "2"],
            2,
            "give one of: a policy DIRECTORY, --random, --zeros",
        ),
        (
            ["imitation", "--dataset", "{tmp}/full", "--policy", "act", "--steps", "2", "--output", "{tmp}/o"],
            2,
            "joshua-train: error: dataset {tmp}/full is not a LeRobot dataset (no meta/info.json)",
        ),
    ],
)
def test_bad_input_is_one_line_and_an_exit_code(tmp_path, args, code, message):
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "notes.txt").write_text("keep me\n")
    result = run("joshua_runtime.train.cli", *[a.format(tmp=tmp_path) for a in args], check=False)
    assert result.returncode == code
    assert message.format(tmp=tmp_path) in result.stderr
    assert "Traceback" not in result.stderr
    assert (tmp_path / "full" / "notes.txt").read_text() == "keep me\n"
