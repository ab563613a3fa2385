"""`joshua-train imitation` fits the data and the machine: device, image size, data-loader workers, processes.

Tiny ACTs on tiny recordings (testsupport/tiny_act.py): 64x48 frames resized to 32x24, a few steps.
Two CPU processes (gloo) must lower the loss as one process does: compared by trend, never by time.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from joshua_runtime.ai.images import resize
from joshua_runtime.train.lerobot_hooks import ResizeFrames
from testsupport import tiny_act

TOOL_TIMEOUT_S = 600
SIZE = (64, 48)
TRAINED_SIZE = (32, 24)
# Enough for the trend: at 20 steps the last tenth's loss is about a fifth of the first's (0.996 -> 0.202,
# one process), far under MAX_LOSS_RATIO; each step more costs about 0.1 CPU-s in each of three processes.
STEPS = 20
# The last tenth of the run against the first: both runs must have learnt, by a clear margin.
MAX_LOSS_RATIO = 0.7
# The two-process run ends within this factor of the one-process run's final loss.
PROCESS_AGREEMENT = 2.0


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    return tiny_act.record_dataset(tmp_path_factory.mktemp("recording") / "dataset", 3, 30, size=SIZE)


def joshua_train(*args, check=True):
    env = {**os.environ, "HF_HUB_OFFLINE": "1"}
    result = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.train.cli", *map(str, args)],
        capture_output=True,
        text=True,
        env=env,
        timeout=TOOL_TIMEOUT_S,
    )
    if check:
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result


def imitation(dataset, output, *extra):
    joshua_train(
        "imitation", "--dataset", dataset, "--policy", "act", "--steps", STEPS, "--output", output,
        "--batch-size", 4, "--image-size", "x".join(map(str, TRAINED_SIZE)), *extra,
    )  # fmt: skip
    pretrained = output / "checkpoints" / "last" / "pretrained_model"
    return pretrained, json.loads((pretrained / "joshua_policy.json").read_text())


def test_training_resizes_frames_as_serving_does():
    frame = tiny_act.frame_image(0.3, *SIZE)
    import torch

    tensor = torch.from_numpy(frame).permute(2, 0, 1).float() / 255.0
    trained = ResizeFrames(*TRAINED_SIZE)(tensor).permute(1, 2, 0).numpy()
    served = resize(frame, *TRAINED_SIZE).astype(np.float32) / 255.0
    assert trained.shape == served.shape == (TRAINED_SIZE[1], TRAINED_SIZE[0], 3)
    assert np.max(np.abs(trained - served)) <= 1.0 / 255.0


@pytest.mark.timeout(2 * TOOL_TIMEOUT_S)  # two trainings, each bounded by its own timeout: 160 s beside 6 burners
def test_two_cpu_processes_lower_the_loss_as_one_process_does(recording, tmp_path, monkeypatch):
    # PyTorch's launcher keeps its logs in a directory of its own in TMPDIR. A short one: a data loader worker
    # hands tensors over through a Unix socket made there, whose path must fit in 107 bytes.
    temporary = Path(tempfile.mkdtemp(prefix="two-processes-"))
    monkeypatch.setenv("TMPDIR", str(temporary))
    try:
        one_dir, one = imitation(recording, tmp_path / "one", "--device", "auto", "--workers", 1)
        two_dir, two = imitation(recording, tmp_path / "two", "--device", "cpu", "--workers", 0, "--processes", 2)
        assert list(temporary.iterdir()) == []
    finally:
        shutil.rmtree(temporary, ignore_errors=True)
    config = json.loads((one_dir / "config.json").read_text())
    assert config["input_features"]["observation.images.camera"]["shape"] == [3, TRAINED_SIZE[1], TRAINED_SIZE[0]]
    assert one["image_size"] == list(TRAINED_SIZE) and one["device"] == "cpu" and one["processes"] == 1
    assert one["distributed_backend"] is None
    assert two["processes"] == 2 and two["distributed_backend"] == "gloo" and (two_dir / "model.safetensors").is_file()
    for run in (one, two):
        losses = [point["loss"] for point in run["loss"]]
        assert losses[-1] < MAX_LOSS_RATIO * losses[0], run["loss"]
    assert two["loss"][-1]["loss"] < PROCESS_AGREEMENT * one["loss"][-1]["loss"], (one["loss"], two["loss"])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--image-size", "64"], "image size '64' is not WIDTHxHEIGHT (e.g. 160x120)"),
        (["--image-size", "0x5"], "image size '0x5' must be positive"),
        (["--processes", "0"], "joshua-train: error: --processes must be positive, got 0"),
        (["--workers", "-1"], "joshua-train: error: --workers must be 0 or more, got -1"),
        (["--device", "mps"], "joshua-train: error: device 'mps' requested but this machine has none"),
        (["--device", "tpu"], "argument --device: invalid choice: 'tpu'"),
    ],
)
def test_bad_training_options_are_one_line_and_exit_code_2(recording, tmp_path, args, message):
    result = joshua_train(
        "imitation", "--dataset", recording, "--policy", "act", "--steps", 1, "--output", tmp_path / "o", *args,
        check=False,
    )  # fmt: skip
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "o").exists()
