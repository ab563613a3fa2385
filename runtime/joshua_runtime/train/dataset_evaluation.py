"""`joshua-train evaluate MODEL --dataset DIR --episodes IDS`: how far a policy's actions are from held-out demonstrations.

Every frame of the held-out episodes goes through the policy as an INFERENCE node would feed it (the
camera frames resized to the policy's input with images.resize, the joint state, the episode's task
as instruction; the policy reset at each episode start), and its action is compared with the action
recorded in that frame. The baseline replays the mean action of the dataset's other episodes. Per
joint: mean absolute error (MAE) and root mean square error (RMSE), in the dataset's units.
"""

from pathlib import Path

import numpy as np

from joshua_runtime.ai import data_only, model_files
from joshua_runtime.ai import features as keys
from joshua_runtime.errors import SettingsError
from joshua_runtime.train import action_plot
from joshua_runtime.train.imitation import check_dataset, check_episodes


def parse_episodes(text: str) -> list[int]:
    """Episode indices from `3`, `3,5` or `2-4` (and mixtures): sorted, without repeats."""
    episodes = set()
    for part in text.split(","):
        first, _, last = part.strip().partition("-")
        if not first.isdigit() or (last and not last.isdigit()):
            raise SettingsError(f"--episodes {text!r} is not a list of episode indices (e.g. 8,9 or 8-9)")
        episodes.update(range(int(first), int(last or first) + 1))
    return sorted(episodes)


def recorded_actions(dataset: Path) -> tuple[np.ndarray, np.ndarray]:
    """(episode index of every frame, action of every frame) from the dataset's parquet files."""
    import pandas

    files = sorted((dataset / "data").glob("*/*.parquet"))
    table = pandas.concat([pandas.read_parquet(f, columns=["episode_index", keys.ACTION]) for f in files])
    return table["episode_index"].to_numpy(), np.stack(table[keys.ACTION].to_numpy()).astype(np.float64)


def errors(predicted: np.ndarray, recorded: np.ndarray, joints: list[str]) -> dict:
    difference = predicted - recorded
    mae = np.mean(np.abs(difference), axis=0)
    rmse = np.sqrt(np.mean(difference**2, axis=0))
    return {
        "mae": {joint: round(float(value), 6) for joint, value in zip(joints, mae)},
        "rmse": {joint: round(float(value), 6) for joint, value in zip(joints, rmse)},
        "mean_mae": round(float(np.mean(mae)), 6),
        "mean_rmse": round(float(np.mean(rmse)), 6),
    }


def evaluate(model: Path, dataset: Path, episodes: list[int], plot: Path, device: str = "cpu") -> dict:
    """Compare the policy in `model` with episodes `episodes` of `dataset`; write the plot; return the result."""
    dataset = check_dataset(dataset)
    path = Path(model).expanduser()
    if not path.is_dir():
        raise SettingsError(f"policy directory {model} does not exist")
    policy_dir = model_files.policy_directory(path)
    data_only.check(policy_dir)
    check_episodes(dataset, episodes)
    frame_episodes, actions = recorded_actions(dataset)
    others = ~np.isin(frame_episodes, episodes)
    if not others.any():
        raise SettingsError("every episode is held out: the mean-action baseline needs at least one other episode")
    mean_action = actions[others].mean(axis=0)
    joints = _joint_names(dataset, actions.shape[1])
    recorded, predicted, starts, tasks = _replay(policy_dir, dataset, episodes, device)
    result = {
        "dataset": str(dataset),
        "model": str(policy_dir),
        "episodes": episodes,
        "frames": int(len(recorded)),
        "tasks": tasks,
        "joints": joints,
        "policy": errors(predicted, recorded, joints),
        "mean_action": errors(np.broadcast_to(mean_action, recorded.shape), recorded, joints),
    }
    title = f"{Path(model).name} on episodes {','.join(map(str, episodes))} of {dataset.name}"
    result["plot"] = str(action_plot.write(plot, joints, recorded, predicted, mean_action, starts, title))
    return result


def _replay(policy_dir: Path, dataset: Path, episodes: list[int], device: str):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    from joshua_runtime.ai.images import resize
    from joshua_runtime.ai.policy_runner import PolicyRunner

    runner = PolicyRunner(policy_dir, device)
    frames = LeRobotDataset(f"local/{dataset.name}", root=dataset, episodes=episodes, video_backend="pyav")
    recorded, predicted, starts, tasks = [], [], [], []
    episode = None
    for index in range(len(frames)):
        item = frames[index]
        if int(item["episode_index"]) != episode:
            episode = int(item["episode_index"])
            starts.append(index)
            tasks.append(item.get("task", ""))
            runner.reset()
        observation = {}
        for key, (_, height, width) in runner.shapes.images.items():
            pixels = (item[key].permute(1, 2, 0).numpy() * 255.0).round().astype(np.uint8)
            observation[key] = resize(pixels, width, height)
        if runner.shapes.state_size is not None:
            observation[keys.STATE] = item[keys.STATE].numpy().astype(np.float32)
        predicted.append(runner.act(observation, task=item.get("task", "")))
        recorded.append(item[keys.ACTION].numpy())
    return np.array(recorded, np.float64), np.array(predicted, np.float64), starts, tasks


def _joint_names(dataset: Path, size: int) -> list[str]:
    import json

    names = json.loads((dataset / "meta" / "info.json").read_text())["features"][keys.ACTION].get("names")
    if isinstance(names, list) and len(names) == size:
        return [keys.joint_name(str(name)) for name in names]
    return [f"action {index}" for index in range(size)]


def summary(result: dict) -> str:
    """A few readable lines: per-joint MAE of the policy and of the mean action."""
    width = max(len(joint) for joint in result["joints"])
    lines = [
        f"{result['frames']} frames of episodes {','.join(map(str, result['episodes']))}: "
        f"mean absolute error {result['policy']['mean_mae']:.4f} (mean action {result['mean_action']['mean_mae']:.4f})"
    ]
    for joint in result["joints"]:
        lines.append(
            f"  {joint:<{width}}  policy MAE {result['policy']['mae'][joint]:.4f} RMSE {result['policy']['rmse'][joint]:.4f}"
            f"   mean action MAE {result['mean_action']['mae'][joint]:.4f} RMSE {result['mean_action']['rmse'][joint]:.4f}"
        )
    lines.append(f"plot: {result['plot']}")
    return "\n".join(lines)
