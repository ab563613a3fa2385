"""`joshua-train imitation`: LeRobot's own training loop on a recorded dataset, offline and on the CPU.

Small models (ImitationSizes), no pretrained vision backbone (nothing is downloaded), images read
with PyAV, LeRobot's progress bar. OUTPUT is LeRobot's output directory (it must not exist yet);
the policy is saved by LeRobot's `save_pretrained` in `OUTPUT/checkpoints/last/pretrained_model`,
where `joshua_policy.json` records the dataset, steps, seed and, when asked, an evaluation.
"""

import sys
from pathlib import Path

from joshua_runtime.ai import saved_policy
from joshua_runtime.errors import SettingsError

POLICIES = ("act", "diffusion")
# One thread per process: on a shared CPU more threads make each small update slower, not faster.
TORCH_THREADS = 1
PRETRAINED_SUBDIRECTORY = Path("checkpoints/last/pretrained_model")
# Sizes that train in minutes on a CPU and still fit small demonstration datasets.
ACT_SIZES = {
    "dim_model": 64,
    "n_heads": 2,
    "dim_feedforward": 128,
    "n_encoder_layers": 1,
    "n_decoder_layers": 1,
    "use_vae": False,
    "chunk_size": 10,
    "n_action_steps": 1,
    "optimizer_lr": 1e-3,
    "optimizer_lr_backbone": 1e-4,
}
DIFFUSION_SIZES = {
    "down_dims": (32, 64),
    "diffusion_step_embed_dim": 32,
    "horizon": 8,
    "n_action_steps": 1,
    "spatial_softmax_num_keypoints": 16,
    "num_inference_steps": 10,
    "scheduler_warmup_steps": 10,
    "optimizer_lr": 1e-3,
}


def policy_config(policy: str, sizes: dict | None = None):
    """The LeRobot config of a small `act` or `diffusion` policy for the CPU, without downloads.

    `sizes` replace some of ACT_SIZES / DIFFUSION_SIZES (e.g. a longer `chunk_size`).
    """
    if policy == "act":
        from lerobot.policies.act.configuration_act import ACTConfig

        return ACTConfig(
            device="cpu", push_to_hub=False, pretrained_backbone_weights=None, **{**ACT_SIZES, **(sizes or {})}
        )
    if policy == "diffusion":
        from lerobot.policies.diffusion.configuration_diffusion import DiffusionConfig

        return DiffusionConfig(
            device="cpu", push_to_hub=False, pretrained_backbone_weights=None, **{**DIFFUSION_SIZES, **(sizes or {})}
        )
    raise SettingsError(f"unknown policy {policy!r} (known: {', '.join(POLICIES)})")


def check_dataset(dataset: Path) -> Path:
    dataset = Path(dataset).expanduser().absolute()
    if not (dataset / "meta" / "info.json").is_file():
        raise SettingsError(f"dataset {dataset} is not a LeRobot dataset (no meta/info.json)")
    return dataset


def train(
    dataset: Path, policy: str, steps: int, output: Path, seed: int = 0, batch_size: int = 8, sizes: dict | None = None
) -> Path:
    """Train `policy` (its `sizes` overriding the defaults) on `dataset` for `steps` steps; return the saved policy."""
    dataset = check_dataset(dataset)
    output = Path(output).expanduser().absolute()
    if steps < 1:
        raise SettingsError(f"--steps must be positive, got {steps}")
    if output.exists():
        raise SettingsError(f"output {output} already exists; LeRobot trains into a new directory")
    config = policy_config(policy, sizes)
    from lerobot.configs.default import DatasetConfig, WandBConfig
    from lerobot.configs.train import TrainPipelineConfig
    from lerobot.scripts.lerobot_train import train as lerobot_train

    pipeline = TrainPipelineConfig(
        dataset=DatasetConfig(repo_id=f"local/{dataset.name}", root=str(dataset), video_backend="pyav"),
        policy=config,
        output_dir=output,
        seed=seed,
        num_workers=0,
        batch_size=batch_size,
        steps=steps,
        eval_freq=0,
        log_freq=max(steps // 10, 1),
        save_freq=steps,
        wandb=WandBConfig(enable=False),
    )
    import torch

    torch.set_num_threads(TORCH_THREADS)
    arguments = sys.argv
    sys.argv = arguments[:1]  # LeRobot's config validation reads sys.argv for `--policy.path`
    try:
        lerobot_train(pipeline)
    finally:
        sys.argv = arguments
    pretrained = output / PRETRAINED_SUBDIRECTORY
    saved_policy.write(
        pretrained,
        {
            "kind": saved_policy.KIND_LEROBOT,
            "policy_type": policy,
            "dataset": str(dataset),
            "steps": steps,
            "seed": seed,
            "evaluation": None,
        },
    )
    return pretrained
