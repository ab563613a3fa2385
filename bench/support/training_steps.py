"""Seconds per training step of `joshua-train imitation` and of LeRobot's own `lerobot-train`, same policy, same data.

Both commands run as a user runs them, one after the other on the same recording, with the same ACT
(imitation.ACT_SIZES, no pretrained backbone), batch size, data-loader workers, seed and CPU.
joshua-train trains on one torch thread per process (imitation.TORCH_THREADS); lerobot-train runs
with torch's default threads (one per core) and again with OMP_NUM_THREADS set to the same. Both run
LeRobot's training loop, which logs the mean update and data-loading time of every window of
`log_freq` steps: a step's time is their sum, averaged over every window but the first (start-up,
first batches). The wall time of the whole command is printed next to it.
"""

import os
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from joshua_runtime.train import imitation

COMMAND_TIMEOUT_S = 1800.0  # a full-size run takes minutes on a busy 2-core machine; this only ends a hang
LOG_WINDOWS = 10  # joshua-train imitation logs every steps // 10 steps; lerobot-train is given the same
STEP_LINE = re.compile(r"step:\S+ .*?updt_s:(?P<update>[\d.]+) data_s:(?P<data>[\d.]+)")


@dataclass(frozen=True)
class Run:
    """How both commands train: the shared settings."""

    dataset: Path
    steps: int
    batch_size: int
    workers: int
    image_size: str | None = None  # joshua-train only: --image-size WxH


@dataclass(frozen=True)
class StepTime:
    update_s: float  # forward, backward, optimiser step
    data_s: float  # next batch from the data loader, preprocessing
    wall_s: float  # the whole command: imports, dataset, policy, steps, saving

    @property
    def step_s(self) -> float:
        return self.update_s + self.data_s


def log_freq(steps: int) -> int:
    return max(steps // LOG_WINDOWS, 1)


def joshua_train(run: Run, output: Path) -> list[str]:
    command = [sys.executable, "-m", "joshua_runtime.train.cli", "imitation", "--dataset", str(run.dataset)]
    command += ["--policy", "act", "--steps", str(run.steps), "--output", str(output), "--device", "cpu"]
    command += ["--batch-size", str(run.batch_size), "--workers", str(run.workers)]
    return command + (["--image-size", run.image_size] if run.image_size else [])


def lerobot_train(run: Run, output: Path) -> list[str]:
    """`lerobot-train` with joshua-train imitation's policy and loop settings, as flags."""
    policy = {"type": "act", "pretrained_backbone_weights": None, "device": "cpu", "push_to_hub": False}
    policy.update(imitation.ACT_SIZES)
    flags = {f"policy.{key}": value for key, value in policy.items()}
    flags.update({
        "dataset.repo_id": f"local/{run.dataset.name}", "dataset.root": run.dataset, "dataset.video_backend": "pyav",
        "steps": run.steps, "batch_size": run.batch_size, "num_workers": run.workers, "seed": 0,
        "log_freq": log_freq(run.steps), "save_freq": run.steps, "eval_freq": 0, "wandb.enable": False,
        "output_dir": output,
    })  # fmt: skip
    return [
        str(Path(sys.executable).parent / "lerobot-train"),
        *(f"--{key}={_flag(value)}" for key, value in flags.items()),
    ]


def _flag(value) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return str(value).lower()
    return str(value)


def environment(threads: int | None) -> dict:
    """This process's environment with OMP_NUM_THREADS set to `threads`, or unset (None: torch's default)."""
    env = {key: value for key, value in os.environ.items() if key != "OMP_NUM_THREADS"}
    return env if threads is None else {**env, "OMP_NUM_THREADS": str(threads)}


def measure(command: list[str], threads: int | None = None) -> StepTime:
    """Run a training command; its mean step time after the first logged window, and its wall time."""
    start = time.perf_counter()
    result = subprocess.run(
        command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S, env=environment(threads)
    )
    wall = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(f"{Path(command[0]).name} {' '.join(command[1:4])} failed:\n{result.stderr[-3000:]}")
    windows = [match for match in STEP_LINE.finditer(result.stdout + result.stderr)][1:]
    if not windows:
        raise RuntimeError(f"{command[0]} logged fewer than two step windows:\n{result.stderr[-3000:]}")
    update = sum(float(match["update"]) for match in windows) / len(windows)
    data = sum(float(match["data"]) for match in windows) / len(windows)
    return StepTime(update, data, wall)


def row(name: str, time_: StepTime, steps: int) -> str:
    return (
        f"{name:<38} {time_.step_s:6.3f} s/step (update {time_.update_s:.3f}, data {time_.data_s:.3f}), "
        f"{time_.wall_s:6.1f} s wall for {steps} steps"
    )
