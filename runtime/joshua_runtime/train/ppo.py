"""`joshua-train rl`: PPO (stable-baselines3) on a training environment, with checkpoints and resumption.

OUTPUT holds `checkpoints/ppo_<steps>_steps.safetensors` (every `checkpoint_every` steps and at the
end), and at the end `policy.safetensors` and `joshua_policy.json` (see saved_policy.py and
ppo_files.py: weights and JSON, nothing pickled). When OUTPUT already holds a run of the same
environment, training continues from its latest checkpoint up to `steps` in total, with the run's
own PPO settings; a directory holding anything else, or a pickle, is refused rather than read or
overwritten.
"""

import re
from dataclasses import asdict, dataclass
from pathlib import Path

from joshua_runtime.ai import data_only, saved_policy
from joshua_runtime.errors import SettingsError
from joshua_runtime.train import envs
from joshua_runtime.train.evaluation import evaluate

CHECKPOINT_DIR = "checkpoints"
CHECKPOINT_PREFIX = "ppo"
CHECKPOINT_SUFFIX = ".safetensors"
_CHECKPOINT = re.compile(rf"^{CHECKPOINT_PREFIX}_(\d+)_steps\{CHECKPOINT_SUFFIX}$")
# Small MLP policies run fastest on one thread, and leave the other core to the simulation.
TORCH_THREADS = 1
SAMPLES_PER_UPDATE = 1024  # environment steps per PPO update (4 environments x 256 steps)


@dataclass(frozen=True)
class PpoSettings:
    """PPO hyperparameters that learn so100_reach in tens of thousands of steps."""

    n_envs: int = 4
    n_steps: int = 256  # per environment and update
    batch_size: int = 256
    n_epochs: int = 10
    learning_rate: float = 1e-3
    gamma: float = 0.95
    gae_lambda: float = 0.95
    net_arch: tuple[int, ...] = (64, 64)

    @classmethod
    def for_envs(cls, n_envs: int) -> "PpoSettings":
        """The settings for `n_envs` environments: each update learns from SAMPLES_PER_UPDATE steps whatever their number."""
        return cls(n_envs=n_envs, n_steps=max(SAMPLES_PER_UPDATE // n_envs, 1))

    @classmethod
    def of_checkpoint(cls, saved: dict, n_envs: int) -> "PpoSettings":
        """The settings a checkpoint was trained with, on `n_envs` environments."""
        try:
            return cls(**{**saved, "net_arch": tuple(saved["net_arch"]), "n_envs": n_envs})
        except (KeyError, TypeError) as exc:
            raise SettingsError(f"the checkpoint's PPO settings are not this version's: {exc}") from exc


def checkpoint_path(output: Path, steps: int) -> Path:
    return Path(output) / CHECKPOINT_DIR / f"{CHECKPOINT_PREFIX}_{steps}_steps{CHECKPOINT_SUFFIX}"


def latest_checkpoint(output: Path) -> tuple[int, Path] | None:
    """(steps, path) of the most advanced checkpoint in OUTPUT."""
    found = []
    directory = output / CHECKPOINT_DIR
    if directory.is_dir():
        for path in directory.iterdir():
            match = _CHECKPOINT.match(path.name)
            if match:
                found.append((int(match.group(1)), path))
    return max(found, default=None)


def _check_output(output: Path, env_id: str) -> dict | None:
    """The metadata of a run to continue in OUTPUT, None for a fresh run; refuse foreign content."""
    if not output.exists():
        return None
    if not output.is_dir():
        raise SettingsError(f"output {output} exists and is not a directory")
    metadata = saved_policy.read(output)
    if metadata is None:
        if any(output.iterdir()):
            raise SettingsError(f"output {output} is not empty and holds no joshua-train run; choose another directory")
        return None
    if metadata["kind"] != saved_policy.KIND_PPO or metadata.get("env") != env_id:
        raise SettingsError(
            f"output {output} holds a {metadata['kind']} run of {metadata.get('env') or metadata.get('dataset')}, "
            f"not PPO on {env_id}; choose another directory"
        )
    data_only.check(output)
    if latest_checkpoint(output) is None and (output / saved_policy.PPO_FILE).is_file():
        raise SettingsError(
            f"output {output} holds a finished run but no checkpoint to continue from; choose another directory"
        )
    return metadata


def train(
    env_id: str,
    steps: int,
    output: Path,
    seed: int = 0,
    checkpoint_every: int = 10_000,
    eval_episodes: int = 20,
    vec_env: str = "dummy",
    settings: PpoSettings = PpoSettings(),
    progress: bool = True,
    log=print,
    backend: str = "mujoco",
    callbacks: tuple = (),
) -> dict:
    """Train (or continue training) PPO up to `steps` environment steps; return the saved metadata.
    `callbacks`: stable-baselines3 callbacks run beside the checkpoints (bench/train.py times the rollouts)."""
    envs.check_env_id(env_id)
    if steps < 1:
        raise SettingsError(f"--steps must be positive, got {steps}")
    output = Path(output).expanduser()
    previous = _check_output(output, env_id)
    import torch

    from joshua_runtime.ai import ppo_files

    torch.set_num_threads(TORCH_THREADS)
    if previous is not None:
        seed = int(previous.get("seed", seed))
    resume = latest_checkpoint(output) if previous is not None else None
    if resume is not None:
        settings = PpoSettings.of_checkpoint(ppo_files.checkpoint_settings(resume[1]), settings.n_envs)
    environments = _environments(env_id, backend, settings.n_envs, seed, vec_env)
    try:
        model = _model(environments, settings, seed)
        if resume is not None:
            ppo_files.restore_checkpoint(model, resume[1])
            log(f"continuing {env_id} from {resume[1]} ({model.num_timesteps} steps)")
        else:
            output.mkdir(parents=True, exist_ok=True)
            saved_policy.write(output, _metadata(env_id, 0, seed, None))
        remaining = steps - model.num_timesteps
        if remaining > 0:
            checkpoints = ppo_files.SafetensorsCheckpoints(
                lambda done: checkpoint_path(output, done),
                max(checkpoint_every // settings.n_envs, 1),
                asdict(settings),
            )
            model.learn(
                total_timesteps=remaining,
                callback=[checkpoints, *callbacks],
                reset_num_timesteps=False,
                progress_bar=progress,
            )
        if not checkpoint_path(output, model.num_timesteps).is_file():
            ppo_files.save_checkpoint(model, checkpoint_path(output, model.num_timesteps), asdict(settings))
        network = ppo_files.save_policy(model.policy, output)
    finally:
        environments.close()
    result = (
        evaluate(lambda env: lambda obs: model.predict(obs, deterministic=True)[0], env_id, eval_episodes)
        if eval_episodes > 0
        else None
    )
    metadata = {**_metadata(env_id, int(model.num_timesteps), seed, result), "network": network}
    saved_policy.write(output, metadata)
    return metadata


def _model(environments, settings: PpoSettings, seed: int):
    """A new PPO model with these settings (its weights are replaced when a run continues). Its logger writes
    nothing: stable-baselines3's default one makes a directory in /tmp at every run and leaves it there."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.logger import Logger

    model = PPO(
        "MlpPolicy",
        environments,
        n_steps=settings.n_steps,
        batch_size=settings.batch_size,
        n_epochs=settings.n_epochs,
        learning_rate=settings.learning_rate,
        gamma=settings.gamma,
        gae_lambda=settings.gae_lambda,
        policy_kwargs={"net_arch": list(settings.net_arch)},
        seed=seed,
        device="cpu",
        verbose=0,
    )
    model.set_logger(Logger(folder=None, output_formats=[]))
    return model


def _environments(env_id: str, backend: str, n_envs: int, seed: int, vec_env: str):
    """The vectorised training environments on C MuJoCo (dummy, subproc or batch) or on MJX."""
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

    from joshua_runtime.train.reach_vec_env import ReachVecEnv

    if backend == "mjx":
        if env_id != envs.REACH:
            raise SettingsError(f"--backend mjx runs {envs.REACH} only")
        try:
            import jax  # noqa: F401
            from mujoco import mjx  # noqa: F401

            from joshua_runtime.train.mjx_reach import MjxWorlds
        except ImportError as exc:
            raise SettingsError(f"--backend mjx needs the `mjx` extra (mujoco-mjx, jax): {exc}") from exc
        return VecMonitor(ReachVecEnv(MjxWorlds(n_envs), seed))
    if backend != "mujoco":
        raise SettingsError(f"unknown backend {backend!r} (known: mujoco, mjx)")
    if vec_env == "batch":
        if env_id != envs.REACH:
            raise SettingsError(f"--vec-env batch runs {envs.REACH} only")
        from joshua_runtime.train.reach_batch import RolloutWorlds

        return VecMonitor(ReachVecEnv(RolloutWorlds(n_envs), seed))
    vec_class = SubprocVecEnv if vec_env == "subproc" else DummyVecEnv
    return make_vec_env(lambda: envs.make(env_id), n_envs=n_envs, seed=seed, vec_env_cls=vec_class)


def _metadata(env_id: str, steps: int, seed: int, evaluation: dict | None) -> dict:
    from joshua_runtime.sim import arm_task as arm
    from joshua_runtime.train import reach_env

    metadata = {
        "kind": saved_policy.KIND_PPO,
        "env": env_id,
        "steps": steps,
        "seed": seed,
        "evaluation": evaluation,
        "joint_names": list(arm.ARM_JOINTS),
        "observation": env_id,
    }
    if env_id == envs.REACH:
        metadata["goal"] = [round(float(v), 4) for v in reach_env.SERVING_GOAL]
    return metadata


def load(directory: Path):
    """The PPO policy saved in a `joshua-train rl` output directory (weights and JSON; `predict` as stable-baselines3's)."""
    from joshua_runtime.ai import ppo_files

    return ppo_files.load_policy(Path(directory))
