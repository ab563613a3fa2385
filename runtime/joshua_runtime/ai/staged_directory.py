"""Replace a dataset directory by a new version in one atomic step, so a crash never leaves it half-written.

A new episode is written into `<dir>.staging`, a copy of `<dir>` in which files that are never
rewritten (data, videos, episode metadata parquet files) are hard links and the rest (`meta/*.json`,
`meta/tasks.parquet`) are real copies. Once LeRobot has finalised the staging copy, `commit()`
swaps the two directories with renameat2(RENAME_EXCHANGE), then deletes the old version. Where the
kernel or file system cannot exchange, the old version is first renamed to `<dir>.retired`; a crash
between the two renames is repaired by `recover()`, which the recorder runs at start.

The version a commit replaced is kept as `<dir>.undo` until the next commit (or `drop_previous()`),
so `revert()` can put it back in one exchange: that is how the last saved episode is re-recorded.
`recover()` drops it: an undo copy belongs to the writer that made it.
"""

import os
import shutil
from pathlib import Path

from joshua_core.atomic import exchange_directories

STAGING_SUFFIX = ".staging"
RETIRED_SUFFIX = ".retired"
UNDO_SUFFIX = ".undo"
# Parts of a dataset that LeRobot writes once and never rewrites: shared with the staging copy.
_LINKED_TOP_LEVEL = ("data", "videos")
_LINKED_META = ("meta", "episodes")
# Scratch space LeRobot uses while writing an episode: never copied, removed before commit.
_SCRATCH = ("images",)


def staging_path(target: Path) -> Path:
    return target.with_name(target.name + STAGING_SUFFIX)


def retired_path(target: Path) -> Path:
    return target.with_name(target.name + RETIRED_SUFFIX)


def undo_path(target: Path) -> Path:
    return target.with_name(target.name + UNDO_SUFFIX)


def recover(target: Path) -> None:
    """Undo the traces of an interrupted write: drop the staging copy and an undo copy, put back a retired version."""
    shutil.rmtree(staging_path(target), ignore_errors=True)
    drop_previous(target)
    retired = retired_path(target)
    if retired.exists():
        if target.exists():
            shutil.rmtree(retired, ignore_errors=True)
        else:
            os.rename(retired, target)


def prepare(target: Path) -> Path:
    """A fresh staging copy of `target` (a path that does not exist when `target` is absent or empty)."""
    staging = staging_path(target)
    shutil.rmtree(staging, ignore_errors=True)
    if not target.exists() or not any(target.iterdir()):
        return staging
    for source in sorted(target.rglob("*")):
        relative = source.relative_to(target)
        if relative.parts[0] in _SCRATCH or relative.parts[0].startswith("tmp"):
            continue
        destination = staging / relative
        if source.is_dir():
            destination.mkdir(parents=True, exist_ok=True)
            continue
        destination.parent.mkdir(parents=True, exist_ok=True)
        if _never_rewritten(relative):
            try:
                os.link(source, destination)
                continue
            except OSError:
                pass
        shutil.copy2(source, destination)
    staging.mkdir(parents=True, exist_ok=True)
    return staging


def commit(target: Path) -> bool:
    """Make the staging copy the new `target`, atomically; keep the version it replaced as the undo copy.

    Returns whether there was such a version (False: `target` did not exist before)."""
    staging = staging_path(target)
    for scratch in _SCRATCH:
        shutil.rmtree(staging / scratch, ignore_errors=True)
    _fsync_tree(staging)
    drop_previous(target)
    if not target.exists():
        os.rename(staging, target)
        _fsync_directory(target.parent)
        return False
    if exchange_directories(staging, target):
        _fsync_directory(target.parent)
        os.rename(staging, undo_path(target))
        return True
    retired = retired_path(target)
    os.rename(target, retired)
    os.rename(staging, target)
    _fsync_directory(target.parent)
    os.rename(retired, undo_path(target))
    return True


def revert(target: Path, had_previous: bool) -> None:
    """Put back the version the last commit replaced (`had_previous`: what commit returned); with none,
    `target` goes away. Either way in one step: a crash leaves the one version or the other."""
    previous = undo_path(target)
    if not had_previous:
        os.rename(target, previous)
        _fsync_directory(target.parent)
    elif exchange_directories(previous, target):
        _fsync_directory(target.parent)
    else:
        retired = retired_path(target)
        os.rename(target, retired)
        os.rename(previous, target)
        _fsync_directory(target.parent)
        os.rename(retired, previous)
    drop_previous(target)


def drop_previous(target: Path) -> None:
    shutil.rmtree(undo_path(target), ignore_errors=True)


def discard(target: Path) -> None:
    shutil.rmtree(staging_path(target), ignore_errors=True)


def _never_rewritten(relative: Path) -> bool:
    parts = relative.parts
    return parts[0] in _LINKED_TOP_LEVEL or tuple(parts[:2]) == _LINKED_META


def _fsync_tree(root: Path) -> None:
    """Flush every file and directory of `root` to disk, so the swap never exposes unwritten data."""
    for directory, _subdirs, files in os.walk(root):
        for name in files:
            path = os.path.join(directory, name)
            try:
                fd = os.open(path, os.O_RDONLY)
            except OSError:
                continue
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
        _fsync_directory(Path(directory))


def _fsync_directory(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
