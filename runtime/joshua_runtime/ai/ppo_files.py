"""A PPO policy as data: weights in safetensors and a network description in JSON, written and read without pickle.

`policy.safetensors` holds the tensors of stable-baselines3's ActorCriticPolicy (its state_dict); the
`network` field of joshua_policy.json says what they fit: `observation_size`, `action_low` and
`action_high` (the bounds actions are clipped to), the hidden layers of the actor `pi` and of the
critic `vf`, and the `activation` (one of ACTIVATIONS). Loading builds that network and copies the
tensors in; `predict` is stable-baselines3's own, so a loaded policy acts exactly as the trained one.

A checkpoint (`checkpoints/ppo_<steps>_steps.safetensors`) holds the policy's tensors under `policy.`
and the Adam optimizer's under `optimizer.<parameter>.`; its safetensors metadata (strings) holds
the step and update counts, the optimizer's settings, the network and the PPO settings in JSON.
Importing this module imports torch and stable-baselines3.
"""

import json
from pathlib import Path

import numpy as np
import torch
from gymnasium import spaces
from safetensors import SafetensorError, safe_open
from safetensors.torch import load_file, save_file
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.policies import ActorCriticPolicy

from joshua_runtime.ai import saved_policy
from joshua_runtime.errors import SettingsError

ACTIVATIONS = {"Tanh": torch.nn.Tanh, "ReLU": torch.nn.ReLU}
POLICY_PREFIX = "policy."
OPTIMIZER_PREFIX = "optimizer."
PARTIAL_SUFFIX = ".partial"


def network(policy: ActorCriticPolicy) -> dict:
    """The description of a policy's network that joshua_policy.json keeps."""
    observation, action = policy.observation_space, policy.action_space
    if not (isinstance(observation, spaces.Box) and isinstance(action, spaces.Box)):
        raise SettingsError("only PPO policies with vector observations and actions can be saved")
    if len(observation.shape) != 1 or len(action.shape) != 1:
        raise SettingsError("only PPO policies with vector observations and actions can be saved")
    layers = policy.net_arch
    actor, critic = (layers, layers) if isinstance(layers, list) else (layers.get("pi", []), layers.get("vf", []))
    return {
        "observation_size": int(observation.shape[0]),
        "action_low": [float(v) for v in action.low],
        "action_high": [float(v) for v in action.high],
        "pi": [int(n) for n in actor],
        "vf": [int(n) for n in critic],
        "activation": policy.activation_fn.__name__,
    }


def policy_for(description, source: Path) -> ActorCriticPolicy:
    """A new (untrained) policy with the network `description` read from `source`."""
    try:
        size = int(description["observation_size"])
        low = np.array(description["action_low"], dtype=np.float32)
        high = np.array(description["action_high"], dtype=np.float32)
        layers = {"pi": [int(n) for n in description["pi"]], "vf": [int(n) for n in description["vf"]]}
        activation = ACTIVATIONS[description["activation"]]
        action_space = spaces.Box(low, high, dtype=np.float32)
    except (KeyError, TypeError, ValueError) as exc:
        raise SettingsError(f"{source} describes no PPO network (`network`: {type(exc).__name__} {exc})") from exc
    observation_space = spaces.Box(-np.inf, np.inf, (size,), np.float32)
    return ActorCriticPolicy(
        observation_space, action_space, lambda _: 0.0, net_arch=layers, activation_fn=activation, ortho_init=False
    )


def save_policy(policy: ActorCriticPolicy, directory: Path) -> dict:
    """Write `policy.safetensors` into `directory`; return the network description to keep next to it."""
    description = network(policy)
    _write(Path(directory) / saved_policy.PPO_FILE, _tensors(policy.state_dict()), None)
    return description


def load_policy(directory: Path) -> ActorCriticPolicy:
    """The policy saved in `directory` (policy.safetensors and the network in joshua_policy.json)."""
    directory = Path(directory)
    metadata = saved_policy.read(directory) or {}
    policy = policy_for(metadata.get("network"), directory / saved_policy.METADATA_FILE)
    path = directory / saved_policy.PPO_FILE
    try:
        policy.load_state_dict(load_file(path), strict=True)
    except (OSError, SafetensorError, RuntimeError) as exc:
        raise SettingsError(f"cannot load {path}: {_first_line(exc)}") from exc
    policy.set_training_mode(False)
    return policy


def save_checkpoint(model, path: Path, settings: dict) -> None:
    """Write the policy, the optimizer and the counters of a PPO model, to continue training from later."""
    tensors = {POLICY_PREFIX + key: value for key, value in _tensors(model.policy.state_dict()).items()}
    optimizer = model.policy.optimizer.state_dict()
    for index, state in optimizer["state"].items():
        for key, value in state.items():
            tensors[f"{OPTIMIZER_PREFIX}{index}.{key}"] = torch.as_tensor(value).detach().cpu().contiguous()
    metadata = {
        "num_timesteps": str(int(model.num_timesteps)),
        "n_updates": str(int(model._n_updates)),
        "param_groups": json.dumps(optimizer["param_groups"]),
        "network": json.dumps(network(model.policy)),
        "settings": json.dumps(settings),
    }
    _write(Path(path), tensors, metadata)


def checkpoint_settings(path: Path) -> dict:
    """The PPO settings a checkpoint was trained with."""
    return json.loads(_read_checkpoint(path)[1]["settings"])


def restore_checkpoint(model, path: Path) -> None:
    """Put a checkpoint's policy, optimizer and counters into a PPO model built with the same settings."""
    tensors, metadata = _read_checkpoint(path)
    policy = {key[len(POLICY_PREFIX) :]: value for key, value in tensors.items() if key.startswith(POLICY_PREFIX)}
    state: dict[int, dict] = {}
    for key, value in tensors.items():
        if key.startswith(OPTIMIZER_PREFIX):
            index, name = key[len(OPTIMIZER_PREFIX) :].split(".", 1)
            state.setdefault(int(index), {})[name] = value
    try:
        model.policy.load_state_dict(policy, strict=True)
        model.policy.optimizer.load_state_dict({"state": state, "param_groups": json.loads(metadata["param_groups"])})
        model.num_timesteps = int(metadata["num_timesteps"])
        model._n_updates = int(metadata["n_updates"])
    except (KeyError, ValueError, RuntimeError) as exc:
        raise SettingsError(f"cannot continue from {path}: {_first_line(exc)}") from exc


def convert_pickled(directory: Path) -> None:
    """Replace stable-baselines3's `policy.zip` in `directory` by policy.safetensors and its network.

    This unpickles the zip, which runs whatever it holds: only for files one trusts (`--trust-pickle`)."""
    from stable_baselines3 import PPO

    directory = Path(directory)
    legacy = directory / saved_policy.LEGACY_PPO_FILE
    try:
        model = PPO.load(legacy, device="cpu")
    except Exception as exc:  # a foreign zip fails in many library exception types
        raise SettingsError(f"cannot convert {legacy}: {type(exc).__name__}: {_first_line(exc)}") from exc
    saved_policy.update(directory, network=save_policy(model.policy, directory))
    legacy.unlink()


class SafetensorsCheckpoints(BaseCallback):
    """Writes a checkpoint (save_checkpoint) every `every_calls` calls, one call stepping every environment once."""

    def __init__(self, path_for_steps, every_calls: int, settings: dict):
        super().__init__()
        self.path_for_steps = path_for_steps
        self.every_calls = every_calls
        self.settings = settings

    def _on_step(self) -> bool:
        if self.n_calls % self.every_calls == 0:
            save_checkpoint(self.model, self.path_for_steps(self.model.num_timesteps), self.settings)
        return True


def _tensors(state: dict) -> dict[str, torch.Tensor]:
    return {key: value.detach().cpu().contiguous() for key, value in state.items()}


def _write(path: Path, tensors: dict, metadata: dict | None) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + PARTIAL_SUFFIX)
    save_file(tensors, str(partial), metadata=metadata)
    partial.replace(path)


def _read_checkpoint(path: Path) -> tuple[dict, dict]:
    try:
        with safe_open(str(path), framework="pt", device="cpu") as stream:
            metadata = stream.metadata() or {}
            tensors = {key: stream.get_tensor(key) for key in stream.keys()}
    except (OSError, SafetensorError) as exc:
        raise SettingsError(f"cannot read {path}: {_first_line(exc)}") from exc
    if not {"num_timesteps", "n_updates", "param_groups", "settings"} <= set(metadata):
        raise SettingsError(f"{path} is not a joshua-train checkpoint (its metadata lacks the counters)")
    return tensors, metadata


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__
