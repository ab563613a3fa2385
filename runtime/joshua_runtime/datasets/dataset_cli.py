"""`joshua-dataset`: look at LeRobot datasets and make new ones from them or from bags; every one loads in LeRobotDataset.

    joshua-dataset info DIR [--json]                   fps, features, episodes (frames, seconds, task)
    joshua-dataset view DIR [--port N]                 a local page: each episode's videos, task, joint plots
    joshua-dataset merge OUT DIR DIR...                one dataset of all their episodes, in order
    joshua-dataset split DIR OUT NAME=EPISODES...      e.g. train=0-7 val=8,9 -> OUT/train, OUT/val
    joshua-dataset delete-episode DIR EPISODE... [--output OUT]   without those episodes
    joshua-dataset from-bag BAG OUT --action TOPIC [--inputs TOPIC...] --fps N [--task TEXT]

merge, split and delete-episode are LeRobot's own dataset tools (lerobot.datasets.dataset_tools);
from-bag samples a bag as the recorder would have (datasets/dataset_from_bag.py). New datasets go to
directories that must not exist; delete-episode without --output replaces DIR once the new version
is complete (the old one is removed only then). Exit codes: 0 done, 1 failed, 2 bad command line or
input.
"""

import argparse
import json
import sys
from pathlib import Path

from joshua_runtime.errors import SettingsError

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2
REPO_PREFIX = "local/"
NEW_SUFFIX, OLD_SUFFIX = ".new", ".old"  # beside a dataset delete-episode replaces


def episode_list(text: str) -> list[int]:
    """`0-3,7` -> [0, 1, 2, 3, 7]."""
    episodes = []
    try:
        for part in filter(None, text.split(",")):
            first, _, last = part.partition("-")
            episodes.extend(range(int(first), int(last or first) + 1))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a list of episodes such as 0-3,7") from None
    return episodes


def split_spec(text: str) -> tuple[str, list[int]]:
    name, equals, episodes = text.partition("=")
    if not equals or not name:
        raise argparse.ArgumentTypeError(f"{text!r}: give NAME=EPISODES, e.g. train=0-7")
    return name, episode_list(episodes)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="joshua-dataset", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    info = sub.add_parser("info", help="what a dataset holds")
    info.add_argument("dataset", type=Path)
    info.add_argument("--json", action="store_true")
    view = sub.add_parser("view", help="a local page of the episodes: video, task, joint plots")
    view.add_argument("dataset", type=Path)
    view.add_argument("--bind", default="127.0.0.1", help="address to listen on (default %(default)s)")
    view.add_argument("--port", type=int, default=0, help="0 (default): a free port, printed")
    merge = sub.add_parser("merge", help="one dataset of the episodes of several")
    merge.add_argument("output", type=Path)
    merge.add_argument("datasets", type=Path, nargs="+")
    split = sub.add_parser("split", help="datasets of chosen episodes")
    split.add_argument("dataset", type=Path)
    split.add_argument("output", type=Path)
    split.add_argument("splits", type=split_spec, nargs="+", metavar="NAME=EPISODES")
    delete = sub.add_parser("delete-episode", help="the dataset without some episodes")
    delete.add_argument("dataset", type=Path)
    delete.add_argument("episodes", type=episode_list, nargs="+", metavar="EPISODE")
    delete.add_argument("--output", type=Path, help="write the result here instead of replacing DATASET")
    from_bag = sub.add_parser("from-bag", help="a dataset of one episode from an MCAP bag")
    from_bag.add_argument("bag", type=Path)
    from_bag.add_argument("output", type=Path)
    from_bag.add_argument("--action", required=True, help="the JointState topic recorded as action")
    from_bag.add_argument("--inputs", nargs="*", default=[], help="JointState and Image topics (observations)")
    from_bag.add_argument("--fps", type=int, required=True)
    from_bag.add_argument("--task", default="", help="the episode's task text (default: the bag's name)")
    from_bag.add_argument(
        "--videos", action="store_true", help="store images as videos (AV1), as output_format lerobot"
    )
    from_bag.add_argument("--units", default="SI", choices=("SI", "LEROBOT", "LEROBOT_RANGE"))
    from_bag.add_argument("--calibration-file", default="", help="the follower's calibration (units LEROBOT*)")
    from_bag.add_argument("--robot-type", default="")
    return parser.parse_args(argv)


def load(root: Path):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    from joshua_runtime.datasets.dataset_info import read_info

    read_info(root)  # a clear message for a directory that is no dataset
    return LeRobotDataset(REPO_PREFIX + root.name, root=root, video_backend="pyav")


def new_directory(path: Path) -> Path:
    if path.exists():
        raise SettingsError(f"{path} exists; give a new directory")
    return path


def run(options) -> str:
    """Do the command; the line to print."""
    from joshua_runtime.datasets import dataset_info

    if options.command == "info":
        described = dataset_info.describe(options.dataset)
        return json.dumps(described, indent=2) if options.json else "\n".join(dataset_info.summary(described))
    if options.command == "view":
        from joshua_runtime.datasets import dataset_view

        return dataset_view.serve(options.dataset, options.bind, options.port)
    if options.command == "from-bag":
        from joshua_runtime.datasets.dataset_from_bag import Conversion, convert

        done = convert(
            Conversion(
                options.bag,
                new_directory(options.output),
                options.action,
                options.inputs,
                options.fps,
                options.task or options.bag.name,
                options.robot_type,
                options.videos,
                options.units,
                options.calibration_file,
            )
        )
        return f"wrote {options.output}: 1 episode of {done.frames} frames ({done.skipped} ticks skipped) from {options.bag}"
    from lerobot.datasets import dataset_tools

    if options.command == "merge":
        new_directory(options.output)
        sources = [load(root) for root in options.datasets]
        _check_compatible(sources)
        merged = dataset_tools.merge_datasets(sources, REPO_PREFIX + options.output.name, options.output)
        return f"wrote {options.output}: {merged.meta.total_episodes} episodes, {merged.meta.total_frames} frames"
    if options.command == "split":
        new_directory(options.output)
        source = load(options.dataset)
        splits = dict(options.splits)
        _check_episodes(source, [e for episodes in splits.values() for e in episodes])
        made = dataset_tools.split_dataset(source, splits, options.output)
        return "\n".join(f"wrote {options.output / name}: {d.meta.total_episodes} episodes" for name, d in made.items())
    return _delete(options, dataset_tools)


def _check_episodes(dataset, episodes: list[int]) -> None:
    total = dataset.meta.total_episodes
    outside = sorted({e for e in episodes if not 0 <= e < total})
    if outside:
        raise SettingsError(f"{dataset.root} has episodes 0-{total - 1}; no episode {', '.join(map(str, outside))}")


def _check_compatible(datasets) -> None:
    first = datasets[0]
    for other in datasets[1:]:
        if other.meta.fps != first.meta.fps:
            raise SettingsError(f"{other.root} is recorded at {other.meta.fps} fps, {first.root} at {first.meta.fps}")
        if other.meta.features != first.meta.features:
            raise SettingsError(f"{other.root} has other features than {first.root}; only alike datasets merge")


def _delete(options, dataset_tools) -> str:
    import shutil

    from joshua_core.atomic import exchange_directories

    source = load(options.dataset)
    episodes = sorted({e for group in options.episodes for e in group})
    _check_episodes(source, episodes)
    if len(episodes) == source.meta.total_episodes:
        raise SettingsError(f"that would delete every episode of {options.dataset}")
    if options.output:
        target = new_directory(options.output)
    else:
        target = options.dataset.with_name(options.dataset.name + NEW_SUFFIX)
        shutil.rmtree(target, ignore_errors=True)  # left by an earlier run that was stopped
    result = dataset_tools.delete_episodes(source, episodes, target, REPO_PREFIX + target.name)
    kept = result.meta.total_episodes
    if options.output:
        return f"wrote {target}: {kept} episodes (deleted {', '.join(map(str, episodes))})"
    if not exchange_directories(target, options.dataset):
        old = options.dataset.with_name(options.dataset.name + OLD_SUFFIX)
        options.dataset.rename(old)
        target.rename(options.dataset)
        target = old
    shutil.rmtree(target)
    return f"{options.dataset}: deleted episode {', '.join(map(str, episodes))}; {kept} episodes left"


def main(argv=None) -> int:
    try:
        options = parse_arguments(sys.argv[1:] if argv is None else argv)
    except SystemExit as exc:
        return EXIT_USAGE if exc.code else EXIT_OK
    try:
        print(run(options), flush=True)
    except SettingsError as exc:
        print(f"joshua-dataset: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (OSError, ValueError) as exc:
        print(f"joshua-dataset: error: {options.command} failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        return EXIT_OK
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
