"""`joshua-dataset info|merge|split|delete-episode|from-bag`: every dataset it writes loads in LeRobotDataset.

The source is a bag the project's bag writer wrote (a leader's JointState as action, a follower's
JointState and a camera's Image as observations, 30 messages a second); the leader's first position
counts the messages, so each frame's action says which moment of the bag it was taken from.
The commands that run LeRobot run through the command's `main` in this process, which has LeRobot
loaded already (a process of its own imports torch and LeRobot again: about 5 CPU-s a command); `info`,
which needs neither, and the bad-input cases run the installed `joshua-dataset` itself.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from test_ai_recorder import load

from joshua_runtime.datasets import dataset_cli as dataset_command
from testsupport.arm_bag import CAMERA, FOLLOWER, JOINTS, LEADER, write_arm_bag

DATASET = str(Path(sys.executable).parent / "joshua-dataset")
BAG_HZ, BAG_S, FPS = 30, 2.0, 10
WIDTH, HEIGHT = 8, 6
CLI_TIMEOUT_S = 300


def write_bag(path: Path) -> Path:
    return write_arm_bag(path, BAG_HZ, BAG_S, WIDTH, HEIGHT)


def dataset_cli(env, *arguments) -> subprocess.CompletedProcess:
    return subprocess.run(
        [DATASET, *map(str, arguments)], env=env, capture_output=True, text=True, timeout=CLI_TIMEOUT_S
    )


def ok(env, *arguments) -> str:
    result = dataset_cli(env, *arguments)
    assert result.returncode == 0, result.stderr
    return result.stdout


def ok_here(capsys, *arguments) -> str:
    """`joshua-dataset ARGUMENTS` through its `main` in this process; what it printed."""
    capsys.readouterr()
    code = dataset_command.main(list(map(str, arguments)))
    printed = capsys.readouterr()
    assert code == 0, printed.err
    return printed.out


def actions(dataset, episode: int) -> list[float]:
    start = dataset.meta.episodes[episode]["dataset_from_index"]
    stop = dataset.meta.episodes[episode]["dataset_to_index"]
    return [float(dataset[i]["action"][0]) for i in range(start, stop)]


def test_from_bag_merge_split_delete_and_info_write_datasets_lerobot_loads(tmp_path, ai_env, lerobot_offline, capsys):
    bag = write_bag(tmp_path / "session")
    pick, place = tmp_path / "pick", tmp_path / "place"
    common = ["--action", LEADER, "--inputs", FOLLOWER, CAMERA, "--fps", FPS]
    assert ok_here(capsys, "from-bag", bag, pick, *common, "--task", "pick").startswith(f"wrote {pick}: 1 episode of ")
    ok_here(capsys, "from-bag", bag, place, *common, "--task", "place")
    converted = load(pick)
    assert converted.meta.total_episodes == 1
    assert set(converted.meta.features) >= {"action", "observation.state", "observation.images.camera"}
    taken = actions(converted, 0)
    # A frame every 1/FPS s of the bag: every BAG_HZ / FPS-th message, in order, none missing.
    assert len(taken) >= BAG_S * FPS - 1
    assert np.allclose(np.diff(taken), BAG_HZ / FPS)
    assert converted[0]["observation.images.camera"].shape == (3, HEIGHT, WIDTH)

    merged = tmp_path / "merged"
    ok_here(capsys, "merge", merged, pick, place)
    both = load(merged)
    assert both.meta.total_episodes == 2 and len(both) == 2 * len(taken)
    assert [both.meta.episodes[e]["tasks"] for e in range(2)] == [["pick"], ["place"]]

    described = json.loads(ok(ai_env, "info", merged, "--json"))
    assert [(e["index"], e["frames"], e["tasks"]) for e in described["episodes"]] == [
        (0, len(taken), ["pick"]),
        (1, len(taken), ["place"]),
    ]
    assert described["fps"] == FPS and described["features"]["action"]["names"] == [f"{j}.pos" for j in JOINTS]
    assert f"2 episodes, {2 * len(taken)} frames" in ok(ai_env, "info", merged).splitlines()[0]

    splits = tmp_path / "splits"
    ok_here(capsys, "split", merged, splits, "train=0", "val=1")
    assert [load(splits / name).meta.episodes[0]["tasks"] for name in ("train", "val")] == [["pick"], ["place"]]

    only_place = tmp_path / "only_place"
    ok_here(capsys, "delete-episode", merged, "0", "--output", only_place)
    assert load(only_place).meta.episodes[0]["tasks"] == ["place"] and load(merged).meta.total_episodes == 2
    assert ok_here(capsys, "delete-episode", merged, "1").endswith("1 episodes left\n")
    kept = load(merged)
    assert kept.meta.total_episodes == 1 and kept.meta.episodes[0]["tasks"] == ["pick"]
    assert actions(kept, 0) == taken
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("merged")) == ["merged"]


def test_bad_input_gets_one_line_and_exit_2(tmp_path, ai_env, lerobot_offline):
    bag = write_bag(tmp_path / "session")
    cases = [
        (["info", tmp_path], f"{tmp_path}: not a LeRobot dataset (no meta/info.json)"),
        (["from-bag", bag, tmp_path / "d", "--action", "/nowhere", "--fps", FPS], f"{bag} has no topic /nowhere"),
        (["from-bag", bag, tmp_path / "d", "--action", CAMERA, "--fps", FPS], f"the action topic {CAMERA} is a"),
        (["merge", bag, tmp_path], f"{bag} exists; give a new directory"),
    ]
    for arguments, message in cases:
        result = dataset_cli(ai_env, *arguments)
        assert result.returncode == 2, (arguments, result.stderr)
        assert result.stderr.startswith(f"joshua-dataset: error: {message}") and result.stderr.count("\n") == 1, (
            result.stderr
        )
    assert not (tmp_path / "d").exists()
