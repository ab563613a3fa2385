"""`joshua-train imitation --processes N`: N training processes, one data-parallel LeRobot loop.

The command starts again under PyTorch's launcher (`python -m torch.distributed.run --standalone
--nproc_per_node N`, what `accelerate launch --multi_gpu` runs), one process per GPU or, on the CPU,
N CPU processes. In each, LeRobot's training loop creates its `accelerate.Accelerator`, which reads
the launcher's RANK / WORLD_SIZE: processes exchange gradients over NCCL on GPUs and over gloo on the
CPU, each takes its share of every batch, and only the first (rank 0) logs, saves the policy and
writes joshua_policy.json.
"""

import os
import subprocess
import sys
import tempfile

# The rendezvous of the processes on this machine (`--standalone`: a free local port).
LAUNCHER = ("-m", "torch.distributed.run", "--standalone")


def launched() -> bool:
    """Whether this process is one of several started by the launcher."""
    return world_size() > 1


def world_size() -> int:
    return int(os.environ.get("WORLD_SIZE", "1"))


def is_main_process() -> bool:
    return os.environ.get("RANK", "0") == "0"


def run(processes: int, arguments: list[str]) -> int:
    """Run `joshua-train ARGUMENTS` as `processes` processes; their exit code.

    They run with a temporary directory of their own, removed after: the launcher keeps its logs in a
    `torchelastic_*` directory there and never removes it."""
    command = [sys.executable, *LAUNCHER, f"--nproc_per_node={processes}", "-m", "joshua_runtime.train.cli"]
    with tempfile.TemporaryDirectory(prefix="joshua-train-") as temporary:
        env = {**os.environ, "TMPDIR": temporary}
        return subprocess.run([*command, *arguments], check=False, env=env).returncode
