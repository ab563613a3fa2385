"""`joshua-train evaluate MODEL --dataset DIR --episodes IDS`: per-joint action error on held-out episodes, JSON and PNG.

A tiny ACT trains on episodes 0-2 of a recording (testsupport/tiny_act.py: the action is the next pose,
the state the present one) and is compared with episode 3, which it never saw, next to replaying the
mean action of episodes 0-2; the baseline's figures are recomputed here from the dataset's files.
"""

import json
import os
import re
import subprocess
import sys

import numpy as np
import pandas
import pytest
from PIL import Image

from joshua_core import so100
from testsupport import tiny_act

TOOL_TIMEOUT_S = 600
EPISODES, FRAMES = 4, 30
HELD_OUT = 3
STEPS = 60


def joshua_train(*args, check=True, cwd=None, env=None):
    result = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.train.cli", *map(str, args)],
        capture_output=True,
        text=True,
        env={**(os.environ if env is None else env), "HF_HUB_OFFLINE": "1"},
        timeout=TOOL_TIMEOUT_S,
        cwd=cwd,
    )
    if check:
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """(dataset, policy directory) of an ACT trained on every episode but HELD_OUT."""
    scratch = tmp_path_factory.mktemp("held-out")
    dataset = tiny_act.record_dataset(scratch / "dataset", EPISODES, FRAMES, size=(64, 48))
    joshua_train(
        "imitation", "--dataset", dataset, "--policy", "act", "--steps", STEPS, "--output", scratch / "act",
        "--episodes", f"0-{HELD_OUT - 1}", "--image-size", "32x24", "--batch-size", 8, "--workers", 0,
    )  # fmt: skip
    return dataset, scratch / "act"


def test_held_out_episodes_give_per_joint_errors_against_the_mean_action(trained, tmp_path):
    dataset, policy = trained
    plot = tmp_path / "report" / "held_out.png"
    result = json.loads(
        joshua_train("evaluate", policy, "--dataset", dataset, "--episodes", HELD_OUT, "--plot", plot, "--json").stdout
    )
    joints = list(so100.SO100_JOINTS)
    assert result["episodes"] == [HELD_OUT] and result["frames"] == FRAMES and result["joints"] == joints
    assert result["tasks"] == [tiny_act.TASK]

    table = pandas.concat(pandas.read_parquet(f) for f in sorted((dataset / "data").glob("*/*.parquet")))
    actions = np.stack(table["action"].to_numpy())
    held_out = actions[table["episode_index"].to_numpy() == HELD_OUT]
    mean = actions[table["episode_index"].to_numpy() != HELD_OUT].mean(axis=0)
    expected_mae = np.abs(held_out - mean).mean(axis=0)
    assert [result["mean_action"]["mae"][j] for j in joints] == pytest.approx(expected_mae, abs=1e-5)

    for errors in (result["policy"], result["mean_action"]):
        assert all(errors["rmse"][j] >= errors["mae"][j] - 1e-9 for j in joints)
    assert result["policy"]["mean_mae"] < result["mean_action"]["mean_mae"], result

    image = Image.open(plot)
    assert image.format == "PNG" and result["plot"] == str(plot)
    pixels = np.asarray(image.convert("RGB")).reshape(-1, 3)
    for colour in ((31, 119, 180), (214, 39, 40)):  # recorded, predicted
        assert np.any(np.all(pixels == colour, axis=1)), colour


def test_the_readable_report_names_every_joint_and_the_default_plot(trained, tmp_path):
    dataset, policy = trained
    out = joshua_train("evaluate", policy, "--dataset", dataset, "--episodes", HELD_OUT, cwd=tmp_path).stdout
    assert f"{FRAMES} frames of episodes {HELD_OUT}: mean absolute error" in out
    for joint in so100.SO100_JOINTS:
        assert f"  {joint} " in out
    assert (tmp_path / "evaluation-dataset.png").is_file()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--episodes", "7"], "joshua-train: error: dataset {dataset} has no episode 7 (it has episodes 0-3)"),
        (["--episodes", "0-3"], "every episode is held out: the mean-action baseline needs at least one other"),
        (["--episodes", "two"], "--episodes 'two' is not a list of episode indices (e.g. 8,9 or 8-9)"),
        (["--episodes", "3", "--env", "so100_reach"], "--dataset compares a policy DIRECTORY with held-out episodes"),
    ],
)
def test_bad_evaluation_input_is_one_line(trained, tmp_path, args, message):
    dataset, policy = trained
    result = joshua_train("evaluate", policy, "--dataset", dataset, *args, check=False, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert message.format(dataset=dataset) in result.stderr and "Traceback" not in result.stderr


def test_the_evaluations_torch_workers_sleep_while_they_wait(trained, tmp_path):
    """Spinning OpenMP workers made an evaluation on a busy CPU take 68-102 s instead of 12 s (cpu_threads.py);
    libgomp reports the spin count it runs with when OMP_DISPLAY_ENV=VERBOSE."""
    dataset, policy = trained
    env = {key: value for key, value in os.environ.items() if key not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    result = joshua_train(
        "evaluate", policy, "--dataset", dataset, "--episodes", HELD_OUT, "--plot", tmp_path / "plot.png", "--json",
        env={**env, "OMP_DISPLAY_ENV": "VERBOSE"},
    )  # fmt: skip
    assert re.findall(r"GOMP_SPINCOUNT = '(\d+)'", result.stderr) == ["0"], result.stderr[-3000:]
