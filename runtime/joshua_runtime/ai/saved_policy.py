"""What `joshua-train` writes next to every policy: `joshua_policy.json`, read by the registry and the INFERENCE node.

Fields: `kind` (`sb3-ppo` for a stable-baselines3 PPO policy whose weights are in
`policy.safetensors`; `lerobot` for a policy saved by LeRobot's `save_pretrained` in the same
directory), `env` (the training environment) or `dataset` (the training dataset), `steps`, `seed`,
`evaluation` (`{"success_rate", "mean_return", "episodes", "env"}` or null), and for `sb3-ppo` the
`network` the weights fit (see ai/ppo_files.py), the `observation` layout, `joint_names` (the
joints the actions move) and `goal` (the point an INFERENCE node reaches for, in the world frame
of the model, m).
"""

import json
from pathlib import Path

from joshua_runtime.errors import SettingsError

METADATA_FILE = "joshua_policy.json"
PPO_FILE = "policy.safetensors"
# What stable-baselines3's own save wrote (a zip holding pickles): converted only on request.
LEGACY_PPO_FILE = "policy.zip"
KIND_PPO = "sb3-ppo"
KIND_LEROBOT = "lerobot"
KINDS = (KIND_PPO, KIND_LEROBOT)


def write(directory: Path, metadata: dict) -> None:
    """Write the metadata file (through a temporary file, renamed into place)."""
    if metadata.get("kind") not in KINDS:
        raise ValueError(f"unknown policy kind {metadata.get('kind')!r}")
    path = Path(directory) / METADATA_FILE
    partial = path.with_suffix(".json.partial")
    partial.write_text(json.dumps(metadata, indent=2, sort_keys=True) + "\n")
    partial.replace(path)


def read(directory: Path) -> dict | None:
    """The metadata of a policy directory, or None when it has none."""
    path = Path(directory) / METADATA_FILE
    if not path.is_file():
        return None
    try:
        metadata = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise SettingsError(f"cannot read {path}: {exc}") from exc
    if not isinstance(metadata, dict) or metadata.get("kind") not in KINDS:
        raise SettingsError(f"{path} names no known policy kind (known: {', '.join(KINDS)})")
    return metadata


def is_ppo(directory: Path) -> bool:
    metadata = read(directory)
    return metadata is not None and metadata["kind"] == KIND_PPO


def update(directory: Path, **fields) -> dict:
    """Change some fields of an existing metadata file; return the result."""
    metadata = read(directory)
    if metadata is None:
        raise SettingsError(f"no {METADATA_FILE} in {directory}")
    metadata.update(fields)
    write(directory, metadata)
    return metadata
