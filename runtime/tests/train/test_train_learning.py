"""Learning that can fail: PPO beats random actions on so100_reach, imitation beats replaying zeros.

Margins come from measured runs (bench/train.py, docs/benchmarks.md): after 30k steps PPO reaches the goal in
about half of the episodes (final distance ~0.05 m, return ~-2.4) where random actions never do
(~0.27 m, return ~-12.5); ACT trained briefly on scripted demonstrations reaches the
demonstrated goal (~0.01 m) where goal angles of 0 stay ~0.16 m away.
"""

import json

from train_support import EVALUATION_EPISODES

from joshua_runtime.train import cli, evaluation

MIN_PPO_SUCCESS_RATE = 0.2
MIN_RETURN_GAIN_OVER_RANDOM = 5.0
DEMONSTRATIONS = 3
IMITATION_STEPS = 40
IMITATION_EPISODES = 5
MIN_IMITATION_SUCCESS_RATE = 0.6


def test_ppo_beats_the_random_baseline_by_a_clear_margin(trained_reach):
    _, metadata = trained_reach
    learnt = metadata["evaluation"]
    baseline = evaluation.evaluate(lambda env: None, "so100_reach", EVALUATION_EPISODES)
    assert learnt["episodes"] == baseline["episodes"] == EVALUATION_EPISODES
    assert baseline["success_rate"] <= 0.05
    assert learnt["success_rate"] >= MIN_PPO_SUCCESS_RATE, (learnt, baseline)
    assert learnt["mean_return"] > baseline["mean_return"] + MIN_RETURN_GAIN_OVER_RANDOM, (learnt, baseline)


def test_the_saved_policy_evaluates_exactly_as_the_trained_one(trained_reach):
    """Weights and JSON reproduce the evaluation done in memory at the end of training, to the last digit."""
    output, metadata = trained_reach
    assert cli.run_evaluation(output, "so100_reach", EVALUATION_EPISODES) == metadata["evaluation"]


def test_imitation_of_scripted_demonstrations_beats_replaying_zeros(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("HF_HUB_OFFLINE", "1")
    monkeypatch.setenv("HF_LEROBOT_HOME", str(tmp_path / "lerobot-home"))
    dataset, output = tmp_path / "demos", tmp_path / "act"
    assert cli.main(["demonstrate", "--output", str(dataset), "--episodes", str(DEMONSTRATIONS)]) == 0
    assert (
        cli.main(
            [
                "imitation",
                "--dataset",
                str(dataset),
                "--policy",
                "act",
                "--steps",
                str(IMITATION_STEPS),
                "--output",
                str(output),
            ]
        )
        == 0
    )
    capsys.readouterr()
    assert (
        cli.main(["evaluate", str(output), "--env", "so100_reach", "--episodes", str(IMITATION_EPISODES), "--json"])
        == 0
    )
    learnt = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert (
        cli.main(["evaluate", "--zeros", "--env", "so100_reach", "--episodes", str(IMITATION_EPISODES), "--json"]) == 0
    )
    zeros = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert zeros["success_rate"] == 0.0
    assert learnt["success_rate"] >= MIN_IMITATION_SUCCESS_RATE, (learnt, zeros)
    assert learnt["mean_return"] > zeros["mean_return"], (learnt, zeros)
