"""`joshua-train evaluate --replay --dataset DIR --episodes IDS`: recorded commands drive the simulated arm.

A recording whose arm followed its commands (testsupport/tiny_act.py: the action is the next pose,
the state the present one) is reproduced by the simulation far better than by an arm held still
(episodes 1 and 2: in episode 0 the gripper goes below the simulated gripper's range); the
same recording with one joint's state shifted, as a miscalibrated joint would report it, shows that
joint, and only it, far from the simulation.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pandas
import pytest

from joshua_core import so100
from testsupport import tiny_act

TOOL_TIMEOUT_S = 300
EPISODES, FRAMES = 3, 30
# The simulated arm follows recorded goals this much closer than an arm held still (about 30x here).
SIMULATION_AGREEMENT = 0.2
SHIFTED_JOINT, SHIFT_RAD = "elbow_flex", 0.2


def joshua_train(*args, check=True):
    result = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.train.cli", *map(str, args)],
        capture_output=True,
        text=True,
        env={**os.environ, "HF_HUB_OFFLINE": "1"},
        timeout=TOOL_TIMEOUT_S,
    )
    if check:
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    return tiny_act.record_dataset(tmp_path_factory.mktemp("replay") / "dataset", EPISODES, FRAMES, size=(64, 48))


def shift_state(dataset, joint: str, shift: float) -> None:
    """Add `shift` to one joint of every recorded state, in the dataset's own parquet files."""
    index = list(so100.SO100_JOINTS).index(joint)
    for path in sorted((dataset / "data").glob("*/*.parquet")):
        table = pandas.read_parquet(path)
        states = np.stack(table["observation.state"].to_numpy())
        states[:, index] += shift
        table["observation.state"] = list(states.astype(np.float32))
        table.to_parquet(path)


def test_recorded_commands_move_the_simulated_arm_as_the_recorded_arm_moved(recording):
    result = json.loads(
        joshua_train("evaluate", "--replay", "--dataset", recording, "--episodes", "1-2", "--json").stdout
    )
    joints = list(so100.SO100_JOINTS)
    assert result["episodes"] == [1, 2] and result["joints"] == joints
    assert result["frames"] == 2 * (FRAMES - 1)  # each action judged by the next frame's state
    for joint in joints:
        assert result["simulation"]["mae"][joint] < SIMULATION_AGREEMENT * result["held"]["mae"][joint], result

    table = pandas.concat(pandas.read_parquet(f) for f in sorted((recording / "data").glob("*/*.parquet")))
    states = np.stack(table["observation.state"].to_numpy())
    episodes = [states[table["episode_index"].to_numpy() == episode] for episode in (1, 2)]
    held = np.concatenate([np.abs(frames[1:] - frames[0]) for frames in episodes]).mean(axis=0)
    assert [result["held"]["mae"][j] for j in joints] == pytest.approx(held, abs=1e-5)


def test_a_joint_the_robot_reports_elsewhere_stands_out(recording, tmp_path):
    import shutil

    shifted = tmp_path / "shifted"
    shutil.copytree(recording, shifted)
    shift_state(shifted, SHIFTED_JOINT, SHIFT_RAD)
    out = joshua_train("evaluate", "--replay", "--dataset", shifted, "--episodes", "1").stdout
    result = json.loads(joshua_train("evaluate", "--replay", "--dataset", shifted, "--episodes", "1", "--json").stdout)
    assert result["simulation"]["mae"][SHIFTED_JOINT] == pytest.approx(SHIFT_RAD, abs=0.03)
    others = [joint for joint in so100.SO100_JOINTS if joint != SHIFTED_JOINT]
    assert max(result["simulation"]["mae"][joint] for joint in others) < SHIFT_RAD / 10, result
    assert f"{FRAMES - 1} frames of episodes 1 replayed on builtin:so100" in out
    assert f"  {SHIFTED_JOINT} " in out


@pytest.mark.parametrize(
    "args, message",
    [
        (["--episodes", "5"], "has no episode 5 (it has episodes 0-2)"),
        (["--episodes", "0", "--env", "so100_reach"], "--replay drives the simulation with a --dataset's commands"),
    ],
)
def test_bad_replay_input_is_one_line(recording, args, message):
    result = joshua_train("evaluate", "--replay", "--dataset", recording, *args, check=False)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and "Traceback" not in result.stderr
