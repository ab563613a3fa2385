"""`joshua-train imitation`: LeRobot's own training loop on a recorded dataset, offline.

Small models (ACT_SIZES, DIFFUSION_SIZES, SMOLVLA_SIZES), no pretrained vision backbone (nothing is
downloaded), images read with PyAV, LeRobot's progress bar. Options (TrainingOptions): the device
(`auto` takes the first of cuda, mps, cpu here), an image size every camera frame is resized to
(lerobot_hooks.py; the policy is saved with that input shape, which INFERENCE nodes resize to), the
data-loader workers. Several processes are started by `launch.py`; each runs this loop.
OUTPUT is LeRobot's output directory (it must not exist yet); the policy is saved by LeRobot's
`save_pretrained` in `OUTPUT/checkpoints/last/pretrained_model`, where `joshua_policy.json` records
the dataset, the episodes trained on, its tasks, steps, seed, device, image size, processes (and the
backend they exchanged gradients over), the loss curve and, when asked, an evaluation. A SmolVLA policy keeps its vision-language backbone's configuration and tokenizer in
`pretrained_model/vlm` (model_files.SMOLVLA_BACKBONE), so it loads without the Hub.
"""

import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from joshua_runtime.ai import model_files, saved_policy
from joshua_runtime.errors import SettingsError
from joshua_runtime.train import devices, launch

POLICIES = ("act", "diffusion", "smolvla")
# One thread per process: on a shared CPU more threads make each small update slower, not faster.
TORCH_THREADS = 1
# Frames are decoded and resized by this many data-loader processes while the model trains.
DEFAULT_WORKERS = 2
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
# SmolVLA's action expert trains; its backbone (small_vlm.py unless --vlm names another) stays as it is.
SMOLVLA_SIZES = {
    "chunk_size": 10,
    "n_action_steps": 1,
    "num_steps": 10,
    "expert_width_multiplier": 0.5,
    "scheduler_warmup_steps": 10,
    "scheduler_decay_steps": 1000,
    "optimizer_lr": 1e-3,
    "load_vlm_weights": False,
}


@dataclass(frozen=True)
class TrainingOptions:
    """How a run fits the data and the machine (see the module docstring)."""

    seed: int = 0
    batch_size: int = 8
    device: str = "auto"
    image_size: tuple[int, int] | None = None  # (width, height)
    workers: int = DEFAULT_WORKERS
    vlm: str | None = None  # SmolVLA's backbone: a directory or a Hub id; None: small_vlm.py's
    episodes: list[int] | None = None  # the dataset's episodes to train on; None: all
    sizes: dict | None = None  # replace some of the policy's default sizes


def policy_config(policy: str, sizes: dict | None = None, device: str = "cpu", vlm: str | None = None):
    """The LeRobot config of a small `act`, `diffusion` or `smolvla` policy, without downloads.

    `sizes` replace some of ACT_SIZES / DIFFUSION_SIZES / SMOLVLA_SIZES (e.g. a longer `chunk_size`);
    `vlm` is the SmolVLA backbone directory (see small_vlm.py).
    """
    common = {"device": device, "push_to_hub": False}
    if policy == "act":
        from lerobot.policies.act.configuration_act import ACTConfig

        return ACTConfig(**common, pretrained_backbone_weights=None, **{**ACT_SIZES, **(sizes or {})})
    if policy == "diffusion":
        from lerobot.policies.diffusion.configuration_diffusion import DiffusionConfig

        return DiffusionConfig(**common, pretrained_backbone_weights=None, **{**DIFFUSION_SIZES, **(sizes or {})})
    if policy == "smolvla":
        from lerobot.policies.smolvla.configuration_smolvla import SmolVLAConfig

        backbone = _backbone_sizes(vlm)
        return SmolVLAConfig(**common, vlm_model_name=str(vlm), **{**SMOLVLA_SIZES, **backbone, **(sizes or {})})
    raise SettingsError(f"unknown policy {policy!r} (known: {', '.join(POLICIES)})")


def _backbone_sizes(vlm) -> dict:
    """SmolVLA settings that follow from a small backbone of small_vlm.py (its square image size)."""
    config = Path(str(vlm)) / "config.json"
    if not config.is_file():
        return {}
    import json

    vision = json.loads(config.read_text()).get("vision_config", {})
    side = int(vision.get("image_size", 0))
    return {"resize_imgs_with_padding": (side, side)} if 0 < side < 512 else {}


def check_dataset(dataset: Path) -> Path:
    dataset = Path(dataset).expanduser().absolute()
    if not (dataset / "meta" / "info.json").is_file():
        raise SettingsError(f"dataset {dataset} is not a LeRobot dataset (no meta/info.json)")
    return dataset


def check_episodes(dataset: Path, episodes: list[int]) -> list[int]:
    """`episodes` when the dataset has each of them; a SettingsError naming the first it lacks."""
    import json

    total = int(json.loads((Path(dataset) / "meta" / "info.json").read_text()).get("total_episodes", 0))
    unknown = [episode for episode in episodes if not 0 <= episode < total]
    if unknown:
        raise SettingsError(f"dataset {dataset} has no episode {unknown[0]} (it has episodes 0-{total - 1})")
    return episodes


def check_output(output: Path) -> Path:
    output = Path(output).expanduser().absolute()
    if output.exists():
        raise SettingsError(f"output {output} already exists; LeRobot trains into a new directory")
    return output


def dataset_tasks(dataset: Path) -> list[str]:
    """The task strings of a LeRobot dataset (meta/tasks.parquet), in task index order."""
    import pandas

    tasks = pandas.read_parquet(Path(dataset) / "meta" / "tasks.parquet")
    return [str(task) for task in tasks.sort_values("task_index").index]


def train(dataset: Path, policy: str, steps: int, output: Path, options: TrainingOptions = TrainingOptions()) -> Path:
    """Train `policy` on `dataset` for `steps` steps in this process (one of several when launched so);
    return the saved policy directory."""
    dataset = check_dataset(dataset)
    output = Path(output).expanduser().absolute() if launch.launched() else check_output(output)
    if steps < 1:
        raise SettingsError(f"--steps must be positive, got {steps}")
    if options.workers < 0:
        raise SettingsError(f"--workers must be 0 or more, got {options.workers}")
    if options.episodes is not None:
        check_episodes(dataset, options.episodes)
    device = devices.training_device(options.device)
    with tempfile.TemporaryDirectory(prefix="joshua-train-vlm-") as scratch:
        vlm = options.vlm
        if policy == "smolvla" and vlm is None:
            from joshua_runtime.train import small_vlm

            vlm = str(small_vlm.write(Path(scratch) / model_files.SMOLVLA_BACKBONE))
        config = policy_config(policy, options.sizes, device, vlm)
        losses = _run_lerobot(dataset, config, steps, output, options)
        if not launch.is_main_process():
            return output / PRETRAINED_SUBDIRECTORY
        pretrained = output / PRETRAINED_SUBDIRECTORY
        if policy == "smolvla" and Path(str(vlm)).is_dir():
            _bundle_backbone(Path(str(vlm)), pretrained)
    saved_policy.write(
        pretrained,
        {
            "kind": saved_policy.KIND_LEROBOT,
            "policy_type": policy,
            "dataset": str(dataset),
            "episodes": options.episodes,
            "tasks": dataset_tasks(dataset),
            "steps": steps,
            "seed": options.seed,
            "device": device,
            "image_size": list(options.image_size) if options.image_size else None,
            "processes": launch.world_size(),
            "distributed_backend": losses.backend,
            "loss": losses.curve(),
            "evaluation": None,
        },
    )
    return pretrained


def _run_lerobot(dataset: Path, config, steps: int, output: Path, options: TrainingOptions):
    from lerobot.configs.default import DatasetConfig, WandBConfig
    from lerobot.configs.train import TrainPipelineConfig

    from joshua_runtime.train.lerobot_hooks import LossRecord, instrumented

    pipeline = TrainPipelineConfig(
        dataset=DatasetConfig(
            repo_id=f"local/{dataset.name}", root=str(dataset), episodes=options.episodes, video_backend="pyav"
        ),
        policy=config,
        output_dir=output,
        seed=options.seed,
        num_workers=options.workers,
        batch_size=options.batch_size,
        steps=steps,
        eval_freq=0,
        log_freq=max(steps // 10, 1),
        save_freq=steps,
        wandb=WandBConfig(enable=False),
    )
    import torch

    torch.set_num_threads(TORCH_THREADS)
    record = LossRecord()
    with instrumented(options.image_size, record) as lerobot_train:
        lerobot_train.train(pipeline)
    return record


def _bundle_backbone(vlm: Path, pretrained: Path) -> None:
    """Copy the backbone into the saved policy and point the policy's config and tokenizer step at the copy."""
    import json

    bundled = pretrained / model_files.SMOLVLA_BACKBONE
    shutil.copytree(vlm, bundled)
    config_path = pretrained / model_files.CONFIG_FILE
    config = json.loads(config_path.read_text())
    config["vlm_model_name"] = str(bundled)
    config_path.write_text(json.dumps(config, indent=4) + "\n")
    preprocessor_path = pretrained / model_files.PROCESSOR_FILES[0]
    pipeline = json.loads(preprocessor_path.read_text())
    for step in pipeline["steps"]:
        if step.get("registry_name") == model_files.TOKENIZER_STEP:
            step["config"]["tokenizer_name"] = str(bundled)
    preprocessor_path.write_text(json.dumps(pipeline, indent=2) + "\n")


def loss_summary(metadata: dict) -> str:
    """One line: the mean training loss of the first and of the last window of the run."""
    curve = metadata.get("loss") or []
    if not curve:
        return "training loss: not recorded"
    processes = metadata.get("processes", 1)
    where = f" (process 1 of {processes})" if processes > 1 else ""
    return (
        f"training loss{where}: {curve[0]['loss']:.4f} over steps 1-{curve[0]['step']}, "
        f"{curve[-1]['loss']:.4f} over steps {curve[-2]['step'] + 1 if len(curve) > 1 else 1}-{curve[-1]['step']}"
    )
