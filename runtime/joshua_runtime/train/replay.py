"""`joshua-train evaluate --replay --dataset DIR --episodes IDS`: does the simulated arm move as the recorded one did?

Each held-out episode's recorded commands (the `action` of every frame: goal joint positions) drive
the project's MuJoCo SO-100 (sim/engine.py on MODEL, stepped in this process): the arm starts at the
episode's first recorded state, and for each frame gets that frame's action as its goals and runs
one frame period (1 / fps) of physics; the joint positions it reaches are compared with the state
recorded in the next frame. The baseline is an arm that never moves (the first state held). Per
joint: MAE and RMSE in radians, for datasets recorded in SI units (joint positions in radians).
"""

from pathlib import Path

import numpy as np

from joshua_runtime.ai import features as keys
from joshua_runtime.errors import SettingsError
from joshua_runtime.train.dataset_evaluation import errors
from joshua_runtime.train.imitation import check_dataset, check_episodes

MODEL = "builtin:so100"


def recorded_episode_frames(dataset: Path, episodes: list[int]) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """{episode: (states, actions)} of `episodes`, each frames x joints, in frame order."""
    import pandas

    columns = ["episode_index", "frame_index", keys.STATE, keys.ACTION]
    files = sorted((dataset / "data").glob("*/*.parquet"))
    table = pandas.concat([pandas.read_parquet(f, columns=columns) for f in files])
    table = table[table["episode_index"].isin(episodes)].sort_values(["episode_index", "frame_index"])
    return {
        int(episode): (np.stack(frames[keys.STATE].to_numpy()), np.stack(frames[keys.ACTION].to_numpy()))
        for episode, frames in table.groupby("episode_index")
    }


def feature_joints(dataset: Path, feature: str) -> list[str]:
    import json

    names = json.loads((dataset / "meta" / "info.json").read_text())["features"].get(feature, {}).get("names")
    if not isinstance(names, list):
        raise SettingsError(f"dataset {dataset} does not name the joints of {feature!r}")
    return [keys.joint_name(str(name)) for name in names]


def simulate(states: np.ndarray, actions: np.ndarray, joints: list[str], fps: float) -> np.ndarray:
    """The joint positions the simulated arm reaches after each frame's action (frames x joints)."""
    from joshua_runtime.sim.engine import SimulationEngine
    from joshua_runtime.sim.model import load_model

    engine = SimulationEngine(load_model(MODEL), realtime_factor=0)
    group = engine.joints(joints, actuated=True)
    engine.data.qpos[group.qpos] = states[0]
    engine.command(group, states[0])
    steps = max(round(1.0 / (fps * engine.model.opt.timestep)), 1)
    reached = []
    for action in actions:
        engine.command(group, action)
        engine.step(steps)
        reached.append(engine.read(group).positions)
    return np.array(reached)


def replay(dataset: Path, episodes: list[int]) -> dict:
    """Drive the simulation with the recorded commands of `episodes`; its per-joint error and the baseline's."""
    import json

    dataset = check_dataset(dataset)
    check_episodes(dataset, episodes)
    joints = feature_joints(dataset, keys.ACTION)
    if feature_joints(dataset, keys.STATE) != joints:
        raise SettingsError(f"dataset {dataset}: the state and the action name different joints")
    fps = float(json.loads((dataset / "meta" / "info.json").read_text())["fps"])
    simulated, held, recorded = [], [], []
    for states, actions in recorded_episode_frames(dataset, episodes).values():
        # the action of frame i is judged by the state of frame i + 1: the last action has none
        simulated.append(simulate(states, actions[:-1], joints, fps))
        held.append(np.broadcast_to(states[0], states[1:].shape))
        recorded.append(states[1:])
    recorded_all = np.concatenate(recorded).astype(np.float64)
    return {
        "dataset": str(dataset),
        "model": MODEL,
        "episodes": episodes,
        "frames": int(len(recorded_all)),
        "joints": joints,
        "simulation": errors(np.concatenate(simulated), recorded_all, joints),
        "held": errors(np.concatenate(held).astype(np.float64), recorded_all, joints),
    }


def summary(result: dict) -> str:
    """A few readable lines: per-joint MAE of the simulated arm and of the arm held still."""
    width = max(len(joint) for joint in result["joints"])
    lines = [
        f"{result['frames']} frames of episodes {','.join(map(str, result['episodes']))} replayed on {result['model']}: "
        f"mean absolute error {result['simulation']['mean_mae']:.4f} rad (held still {result['held']['mean_mae']:.4f})"
    ]
    for joint in result["joints"]:
        lines.append(
            f"  {joint:<{width}}  simulation MAE {result['simulation']['mae'][joint]:.4f} "
            f"RMSE {result['simulation']['rmse'][joint]:.4f}   held still MAE {result['held']['mae'][joint]:.4f}"
        )
    return "\n".join(lines)
