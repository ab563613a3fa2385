"""The files of a saved LeRobot policy, read without importing torch.

A policy directory is what `PreTrainedPolicy.save_pretrained` (and `lerobot-train`'s checkpoints)
write: `config.json` (with the policy `type`), `model.safetensors`, and the processor pipelines
`policy_preprocessor.json` / `policy_postprocessor.json` with their state files. A training output
directory (`.../checkpoints/last/pretrained_model`) or a checkpoint directory is accepted too.

LeRobot policies do not keep the names of their features. They are looked up, in this order, in
`joshua_features.json` next to the policy (written by `joshua-registry import`), then in the
`meta/info.json` of the dataset named by the policy's `train_config.json` when that dataset is on
this machine.
"""

import json
import os
from pathlib import Path

from joshua_core.models import POLICY_TYPES as SUPPORTED_POLICY_TYPES  # noqa: F401 (read by the policy loaders)
from joshua_runtime.errors import SettingsError

CONFIG_FILE = "config.json"
WEIGHTS_FILE = "model.safetensors"
PROCESSOR_FILES = ("policy_preprocessor.json", "policy_postprocessor.json")
# The processor steps LeRobot saves for ACT, Diffusion and SmolVLA policies (by their registry names): each
# is data in, data out. A pipeline naming any other step is refused (see data_only.py).
TOKENIZER_STEP = "tokenizer_processor"
ALLOWED_PROCESSOR_STEPS = (
    "device_processor",
    "normalizer_processor",
    "rename_observations_processor",
    "smolvla_new_line_processor",
    "to_batch_processor",
    TOKENIZER_STEP,
    "unnormalizer_processor",
)
# Where a SmolVLA policy keeps its vision-language backbone's configuration and tokenizer (JSON files),
# which its config.json and its tokenizer step are pointed at when it is loaded.
SMOLVLA_BACKBONE = "vlm"
TRAIN_CONFIG_FILE = "train_config.json"
FEATURE_NAMES_FILE = "joshua_features.json"
# Where a policy can sit below a directory given by the user, tried in order.
_POLICY_SUBDIRECTORIES = ("", "pretrained_model", "checkpoints/last/pretrained_model")


def policy_directory(path: str | Path) -> Path:
    """The directory holding config.json and the weights, at or below `path`."""
    base = Path(path).expanduser()
    if not base.is_dir():
        raise SettingsError(f"model path {path} is not a directory")
    for sub in _POLICY_SUBDIRECTORIES:
        candidate = base / sub if sub else base
        if (candidate / CONFIG_FILE).is_file():
            missing = [name for name in (WEIGHTS_FILE, *PROCESSOR_FILES) if not (candidate / name).is_file()]
            if missing:
                raise SettingsError(f"policy in {candidate} lacks {', '.join(missing)} (save it with LeRobot 0.4)")
            return candidate
    raise SettingsError(f"no LeRobot policy (config.json) in {path}")


def policy_config(directory: Path) -> dict:
    """The parsed config.json of a policy directory."""
    try:
        config = json.loads((directory / CONFIG_FILE).read_text())
    except (OSError, ValueError) as exc:
        raise SettingsError(f"cannot read {directory / CONFIG_FILE}: {exc}") from exc
    if not isinstance(config, dict) or not isinstance(config.get("type"), str):
        raise SettingsError(f"{directory / CONFIG_FILE} has no policy type")
    return config


def policy_type(directory: Path) -> str:
    """The policy type (`act`, `diffusion`, ...) recorded in config.json."""
    return policy_config(directory)["type"]


def feature_names(directory: Path) -> dict[str, list[str]]:
    """Names of the policy's vector features (e.g. `{"action": [...], "observation.state": [...]}`)."""
    saved = directory / FEATURE_NAMES_FILE
    if saved.is_file():
        try:
            return json.loads(saved.read_text())
        except (OSError, ValueError):
            return {}
    info = _training_dataset_info(directory)
    if info is None:
        return {}
    names = {}
    for key, feature in info.get("features", {}).items():
        if isinstance(feature, dict) and isinstance(feature.get("names"), list) and len(feature.get("shape", ())) == 1:
            if all(isinstance(name, str) for name in feature["names"]):
                names[key] = feature["names"]
    return names


def write_feature_names(directory: Path, names: dict[str, list[str]]) -> None:
    (directory / FEATURE_NAMES_FILE).write_text(json.dumps(names, indent=2, sort_keys=True) + "\n")


def _training_dataset_info(directory: Path) -> dict | None:
    try:
        dataset = json.loads((directory / TRAIN_CONFIG_FILE).read_text())["dataset"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    candidates = []
    if dataset.get("root"):
        candidates.append(Path(dataset["root"]))
    if dataset.get("repo_id"):
        candidates.append(_lerobot_home() / str(dataset["repo_id"]))
    for root in candidates:
        try:
            return json.loads((root / "meta" / "info.json").read_text())
        except (OSError, ValueError):
            continue
    return None


def _lerobot_home() -> Path:
    if os.environ.get("HF_LEROBOT_HOME"):
        return Path(os.environ["HF_LEROBOT_HOME"]).expanduser()
    hf_home = os.environ.get("HF_HOME") or os.path.join(os.path.expanduser("~"), ".cache", "huggingface")
    return Path(hf_home) / "lerobot"
