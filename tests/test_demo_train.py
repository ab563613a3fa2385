"""`make demo-train` at a small size: demonstrations, ACT, registry, and the policy driving the simulated arm.

The same commands as the full walkthrough (DEMO_* variables only shrink it): its evidence line must
show the served policy commanding the MuJoCo SO-100 and bringing the grasp point toward the goal.
DEMO_SECONDS counts from the policy's first command, so a few seconds show it however long the policy
node takes to load LeRobot on a busy machine.
"""

import re
import subprocess
import sys

import pytest

from testsupport.joshuac_cli import ROOT

pytestmark = [pytest.mark.ai, pytest.mark.process, pytest.mark.xdist_group("checkout")]  # `make setup`

SMALL = ["DEMO_EPISODES=2", "DEMO_STEPS=20", "DEMO_EVAL_EPISODES=1", "DEMO_SECONDS=5"]
MAKE_TIMEOUT_S = 300
EVIDENCE = re.compile(
    r"the policy sent (\d+) commands; the grasp point was ([\d.]+) m from the demonstrated goal "
    r"when it started, ([\d.]+) m when the robot stopped"
)


def test_demo_train_drives_the_simulated_arm_with_the_policy_it_trained(tmp_path, ros_env):
    env = {key: value for key, value in ros_env.items() if key != "JOSHUA_MODEL_REGISTRY"}
    output = tmp_path / "demo"
    result = subprocess.run(
        ["make", "-s", "demo-train", f"DEMO_DIR={output}", *SMALL],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=MAKE_TIMEOUT_S,
    )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    evidence = EVIDENCE.search(result.stdout)
    assert evidence, result.stdout[-3000:]
    commands, start_m, end_m = int(evidence[1]), float(evidence[2]), float(evidence[3])
    assert commands > 20
    assert end_m < start_m / 2, f"the arm did not come closer to the goal: {start_m} m -> {end_m} m"
    assert (output / "registry" / "demo_act").is_dir()
    assert "Training:" in result.stderr  # LeRobot's progress bar
    assert "supervisor: ready: 2 of 2 nodes ready" in result.stdout + result.stderr


def test_a_directory_holding_anything_is_refused_and_kept(tmp_path):
    (tmp_path / "notes.txt").write_text("keep me\n")
    result = subprocess.run(
        [sys.executable, ROOT / "scripts" / "demo_train.py", "--output", tmp_path],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2
    assert result.stderr == f"demo-train: error: {tmp_path} exists and is not empty; name a new directory\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]
