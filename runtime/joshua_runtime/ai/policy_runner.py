"""Load a saved LeRobot policy with its own processor pipelines and run one inference step or one chunk.

The weights are read from safetensors (LeRobot's `from_pretrained` of a directory), the pipelines
from JSON whose steps are checked first (data_only.check_processor_steps): nothing is unpickled.

Normalisation, batching and device placement are done by the `policy_preprocessor` /
`policy_postprocessor` pipelines saved with the policy (`make_pre_post_processors` with the
policy directory as `pretrained_path`); the observation is prepared with LeRobot's
`predict_action` (images HWC uint8 -> CHW float in [0, 1], batch dimension added), with the task
string that a language-conditioned policy (SmolVLA) takes as its instruction.

A SmolVLA policy reads its vision-language backbone (configuration, tokenizer) from the directory
its config.json and its tokenizer step name. When the policy holds it (`vlm/`, as `joshua-train
imitation` saves it), both are pointed at that copy, whose files data_only has checked, wherever the
policy was moved; otherwise they name a Hugging Face Hub model (`lerobot/smolvla_base` names
`HuggingFaceTB/SmolVLM2-500M-Video-Instruct`), read from the Hub cache. The backbone's weights are
always those of the policy's model.safetensors (`load_vlm_weights` off).
Importing this module imports torch and LeRobot.
"""

import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from joshua_runtime.ai import data_only
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.model_files import SMOLVLA_BACKBONE, SUPPORTED_POLICY_TYPES, TOKENIZER_STEP
from joshua_runtime.errors import SettingsError


@dataclass(frozen=True)
class PolicyShapes:
    """What the policy reads and writes: image features (key -> (C, H, W)), state and action sizes."""

    images: dict[str, tuple[int, ...]]
    state_size: int | None
    action_size: int


def check_device(device: str) -> torch.device:
    """The torch device for `cpu`, `cuda` or `cuda:N`; a SettingsError when CUDA is asked and absent."""
    name = device or "cpu"
    if name == "cpu":
        return torch.device("cpu")
    if name == "cuda" or name.startswith("cuda:"):
        if not torch.cuda.is_available():
            raise SettingsError(f"device {name!r} requested but CUDA is not available on this machine")
        return torch.device(name)
    raise SettingsError(f"unsupported device {name!r} (use cpu or cuda)")


def _read_config(config_class, policy_dir: Path):
    """LeRobot's `PreTrainedConfig.from_pretrained`, which leaves a copy of config.json in the temporary
    directory (a NamedTemporaryFile it does not delete): for the call, the process's temporary directory is
    one of its own, removed after (a node's other threads make no temporary files meanwhile)."""
    previous = tempfile.tempdir
    with tempfile.TemporaryDirectory(prefix="joshua-policy-config-") as scratch:
        tempfile.tempdir = scratch
        try:
            return config_class.from_pretrained(policy_dir)
        finally:
            tempfile.tempdir = previous


class PolicyRunner:
    """A policy, its pre/post-processors and its device, ready for `act(observation)`."""

    def __init__(self, policy_dir: Path, device: str):
        self.device = check_device(device)  # before importing LeRobot, so a missing GPU is reported at once
        data_only.check_processor_steps(policy_dir)  # LeRobot would import and call a `class` named there

        from lerobot.configs.policies import PreTrainedConfig
        from lerobot.policies.factory import get_policy_class, make_pre_post_processors

        config = _read_config(PreTrainedConfig, policy_dir)
        if config.type not in SUPPORTED_POLICY_TYPES:
            raise SettingsError(
                f"policy type {config.type!r} is not supported (supported: {', '.join(SUPPORTED_POLICY_TYPES)})"
            )
        config.device = self.device.type
        config.pretrained_path = policy_dir
        if hasattr(config, "pretrained_backbone_weights"):
            # The checkpoint holds the backbone weights; never fetch torchvision's.
            config.pretrained_backbone_weights = None
        overrides = {"device_processor": {"device": str(self.device)}}
        if hasattr(config, "vlm_model_name"):
            config.load_vlm_weights = False  # the checkpoint holds them
            backbone = Path(policy_dir) / SMOLVLA_BACKBONE
            if backbone.is_dir():
                config.vlm_model_name = str(backbone)
                overrides[TOKENIZER_STEP] = {"tokenizer_name": str(backbone)}
        self.config = config
        self.policy = get_policy_class(config.type).from_pretrained(policy_dir, config=config)
        self.preprocessor, self.postprocessor = make_pre_post_processors(
            config, pretrained_path=str(policy_dir), preprocessor_overrides=overrides
        )
        self.shapes = _shapes(config)

    def reset(self) -> None:
        """Forget queued actions and observation history (after a gap in the inputs)."""
        self.policy.reset()

    def act(self, observation: dict[str, np.ndarray], task: str = "") -> np.ndarray:
        """One action (float32 vector) for an observation of HWC uint8 images and a float32 state; `task`
        is the instruction of a language-conditioned policy."""
        from lerobot.utils.control_utils import predict_action

        action = predict_action(
            dict(observation),
            self.policy,
            self.device,
            self.preprocessor,
            self.postprocessor,
            use_amp=False,
            task=task,
            robot_type="",
        )
        return action.squeeze(0).to("cpu").numpy().astype(np.float32)

    def act_chunk(self, observation: dict[str, np.ndarray], task: str = "") -> np.ndarray:
        """The whole action chunk (steps x action size, float32) the policy predicts for one observation.

        ACT predicts `chunk_size` actions; Diffusion `n_action_steps` from its observation history,
        which this call extends as `select_action` would. Each action is unnormalised by the policy's
        postprocessor, the chunk's steps taken as a batch.
        """
        from lerobot.policies.utils import populate_queues, prepare_observation_for_inference
        from lerobot.utils.constants import ACTION, OBS_IMAGES

        with torch.inference_mode():
            batch = prepare_observation_for_inference(dict(observation), self.device, task, "")
            batch = self.preprocessor(batch)
            if self.config.type == "diffusion":
                batch = {key: value for key, value in batch.items() if key != ACTION}
                if self.config.image_features:
                    batch[OBS_IMAGES] = torch.stack([batch[key] for key in self.config.image_features], dim=-4)
                self.policy._queues = populate_queues(self.policy._queues, batch)
            chunk = self.policy.predict_action_chunk(batch)
            actions = self.postprocessor(chunk.squeeze(0))
        return actions.to("cpu").numpy().astype(np.float32)

    def warm_up(self, task: str = "") -> float:
        """Run one inference on a blank observation, then reset; return its duration in seconds."""
        blank = {key: np.zeros((shape[1], shape[2], shape[0]), np.uint8) for key, shape in self.shapes.images.items()}
        if self.shapes.state_size is not None:
            blank[keys.STATE] = np.zeros(self.shapes.state_size, np.float32)
        start = time.perf_counter()
        self.act(blank, task)
        elapsed = time.perf_counter() - start
        self.reset()
        return elapsed


def _shapes(config) -> PolicyShapes:
    images = {}
    state_size = None
    for key, feature in config.input_features.items():
        kind = feature.type.name
        if kind == "VISUAL" and key.startswith(keys.IMAGE_PREFIX):
            images[key] = tuple(feature.shape)
        elif kind == "STATE" and key == keys.STATE:
            state_size = int(feature.shape[0])
        else:
            raise SettingsError(f"policy input {key} ({kind}) has no ROS source (supported: images and state)")
    action = config.output_features.get(keys.ACTION)
    if action is None or len(action.shape) != 1:
        raise SettingsError("policy has no one-dimensional 'action' output")
    return PolicyShapes(images=images, state_size=state_size, action_size=int(action.shape[0]))
