"""What a LeRobot v3.0 dataset holds, read from its meta/ files alone (no torch): fps, features, episodes, tasks.

`describe(root)` returns a dict (`joshua-dataset info --json` prints it); `summary(info)` the lines
`joshua-dataset info` prints.
"""

import json
from pathlib import Path

import pyarrow.parquet as pq

from joshua_runtime.errors import SettingsError

INFO_FILE = Path("meta") / "info.json"
EPISODES_DIRECTORY = Path("meta") / "episodes"
TASKS_FILE = Path("meta") / "tasks.parquet"
EPISODE_COLUMNS = ("episode_index", "length", "tasks")


def read_info(root: Path) -> dict:
    """meta/info.json of the dataset at `root`; SettingsError when it is no LeRobot dataset."""
    path = root / INFO_FILE
    if not path.is_file():
        raise SettingsError(f"{root}: not a LeRobot dataset (no {INFO_FILE})")
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise SettingsError(f"{path}: unreadable ({exc})") from None


def episodes(root: Path) -> list[dict]:
    """One {"episode_index", "length", "tasks"} per episode, in index order."""
    rows = []
    for path in sorted((root / EPISODES_DIRECTORY).rglob("*.parquet")):
        table = pq.read_table(path, columns=list(EPISODE_COLUMNS))
        rows.extend(table.to_pylist())
    return sorted(rows, key=lambda row: row["episode_index"])


def describe(root: Path) -> dict:
    info = read_info(root)
    features = {
        name: {"dtype": spec["dtype"], "shape": spec["shape"], "names": spec.get("names")}
        for name, spec in info["features"].items()
        if name not in ("timestamp", "frame_index", "episode_index", "index", "task_index")
    }
    return {
        "root": str(root),
        "codebase_version": info.get("codebase_version"),
        "robot_type": info.get("robot_type"),
        "fps": info["fps"],
        "total_episodes": info["total_episodes"],
        "total_frames": info["total_frames"],
        "features": features,
        "episodes": [
            {
                "index": row["episode_index"],
                "frames": row["length"],
                "seconds": row["length"] / info["fps"],
                "tasks": row["tasks"],
            }
            for row in episodes(root)
        ],
    }


def summary(described: dict) -> list[str]:
    lines = [
        f"{described['root']}: LeRobot dataset {described['codebase_version']}, robot {described['robot_type']}, "
        f"{described['fps']} fps, {described['total_episodes']} episodes, {described['total_frames']} frames",
        "features:",
    ]
    for name, spec in described["features"].items():
        names = spec["names"]
        shown = (
            f" ({', '.join(map(str, names))})"
            if isinstance(names, list) and spec["dtype"] not in ("video", "image")
            else ""
        )
        lines.append(f"  {name}: {spec['dtype']} {list(spec['shape'])}{shown}")
    lines.append("episodes:")
    for episode in described["episodes"]:
        lines.append(
            f"  {episode['index']}: {episode['frames']} frames, {episode['seconds']:.2f} s, task: {'; '.join(episode['tasks'])}"
        )
    return lines
