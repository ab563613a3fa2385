"""Proof that joshuac wrote an output directory: the stamp file, its check, and stale staging directories.

`OUT/.joshuac-stamp` lists every file joshuac wrote into OUT with its SHA-256, in the format of
`sha256sum` (`sha256sum -c .joshuac-stamp` checks a tree by hand), after a first line `# joshuac VERSION`
naming the joshuac that wrote it (GNU sha256sum skips lines starting with `#`; stamps without it are read too). A build replaces OUT only when
OUT is missing, empty, or holds exactly files listed in its stamp with unchanged content; anything
else (a file joshuac did not write, an edited generated file, a symbolic link) is refused. A signed build
(`--sign`) also holds `OUT/.joshuac-stamp.sig`, the stamp's signature, which the stamp cannot list.

A build stages its files in `.OUT.XXXXXXXX` next to OUT and holds an flock(2) on that directory
while it works. A staging directory left by a killed build is removed by the next build of OUT
when its name has that pattern, nobody holds its lock, and every file in it is named in its stamp.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import re
import shutil
import stat
from dataclasses import dataclass
from pathlib import Path

from joshua_codegen.version import VERSION

STAMP = ".joshuac-stamp"
SIGNATURE = f"{STAMP}.sig"  # `build --sign`: the stamp's Ed25519 signature (signing.py), not in the stamp itself
STAMP_COMMENT = "# "
_STAMP_LINE = re.compile(r"([0-9a-f]{64})  (.+)")
# Longest list of offending paths printed in a refusal.
SHOWN_PATHS = 10


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def content_bytes(content: str | bytes) -> bytes:
    """A file's content as written: text in UTF-8, binary files (the bundle's wheels) as they are."""
    return content if isinstance(content, bytes) else content.encode("utf-8")


def content_digest(content: str | bytes) -> str:
    """The SHA-256 a stamp lists for a file of this content."""
    return _digest(content_bytes(content))


def stamp_text(files: dict[str, str | bytes]) -> str:
    """The stamp of a set of rendered files: the version line, then one `<sha256>  <path>` line per file, by path."""
    listed = "".join(f"{content_digest(text)}  {path}\n" for path, text in sorted(files.items()))
    return f"{STAMP_COMMENT}joshuac {VERSION}\n{listed}"


def read_stamp(directory: Path) -> dict[str, str] | None:
    """{relative path: sha256} from a directory's stamp, or None when it has no readable stamp."""
    stamp = directory / STAMP
    if stamp.is_symlink() or not stamp.is_file():
        return None
    try:
        text = stamp.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    listed = {}
    for line in text.splitlines():
        if line.startswith(STAMP_COMMENT):
            continue
        match = _STAMP_LINE.fullmatch(line)
        if match is None:
            return None
        listed[match.group(2)] = match.group(1)
    return listed


def _entries(directory: Path):
    """(relative path, lstat) of everything under a directory, not following symbolic links. Paths as
    strings: an output holds thousands of files, and pathlib took most of the check's time."""
    top = os.fspath(directory)
    for root, dirs, files in os.walk(top):
        base = "" if root == top else os.path.relpath(root, top) + "/"
        for name in sorted(dirs + files):
            yield base + name, os.lstat(os.path.join(root, name))


def _read_unchanged(path: str, digest: str) -> os.stat_result | None:
    """The status of the file read at `path` when its content has the SHA-256 `digest`, else None."""
    try:
        with open(os.open(path, os.O_RDONLY | os.O_NOFOLLOW), "rb") as stream:
            status, content = os.fstat(stream.fileno()), stream.read()
    except OSError:
        return None
    return status if _digest(content) == digest else None


def _parents(name: str) -> list[str]:
    """The directories a relative path lies in, as `Path(name).parents` names them (`.` included)."""
    parents = []
    while "/" in name:
        name = name.rpartition("/")[0]
        parents.append(name)
    return [*parents, "."]


@dataclass
class Survey:
    """What an existing output directory holds, against its stamp."""

    stamped: bool  # it has a readable stamp
    foreign: list[str]  # paths joshuac did not write (only the top level when unstamped)
    changed: list[str]  # listed files whose content changed
    unchanged: dict[str, tuple[str, os.stat_result]]  # listed files as listed: {path: (sha256, status as read)}


def survey(directory: Path) -> Survey:
    """Every path of an existing directory that its stamp does not account for, and the files that it does."""
    listed = read_stamp(directory)
    entries = list(_entries(directory))
    if listed is None:
        return Survey(False, [name for name, _ in entries if "/" not in name], [], {})
    parents = {parent for name in listed for parent in _parents(name)}
    found = Survey(True, [], [], {})
    for name, status in entries:
        if stat.S_ISDIR(status.st_mode) and name in parents:
            continue
        if name in (STAMP, SIGNATURE) and stat.S_ISREG(status.st_mode):
            continue
        if name not in listed or not stat.S_ISREG(status.st_mode):
            found.foreign.append(name)
        elif (read := _read_unchanged(os.path.join(directory, name), listed[name])) is None:
            found.changed.append(name)
        else:
            found.unchanged[name] = (listed[name], read)
    return found


def _shown(paths: list[str]) -> str:
    more = f" and {len(paths) - SHOWN_PATHS} more" if len(paths) > SHOWN_PATHS else ""
    return ", ".join(paths[:SHOWN_PATHS]) + more


def refusal(out: Path, shown: Path | None = None) -> str | None:
    """Why `out` may not be replaced by a build, or None when it may (missing, empty, or ours unchanged).

    Messages name `shown` (the path as the user gave it) when given."""
    return inspect_output(out, shown)[0]


def inspect_output(out: Path, shown: Path | None = None) -> tuple[str | None, Survey | None]:
    """(`refusal(out, shown)`, and what `out` holds when it is a directory that could be read)."""
    reason, found = _refusal(out)
    return (reason.replace(str(out), str(shown)) if reason and shown is not None else reason), found


def _refusal(out: Path) -> tuple[str | None, Survey | None]:
    if out.is_symlink():
        return f"{out} is a symbolic link; give the directory itself", None
    if not out.exists():
        return None, None
    if not out.is_dir():
        return f"{out} exists and is not a directory", None
    try:
        if not any(out.iterdir()):
            return None, None
        found = survey(out)
    except OSError as exc:
        return f"cannot read {out}: {exc.strerror or exc}", None
    if not found.stamped:
        return (
            f"{out} is not empty and holds no {STAMP}: refusing to replace a directory joshuac did not write "
            f"(it holds {_shown(found.foreign)}); remove it or choose another output directory"
        ), found
    reasons = []
    if found.foreign:
        reasons.append(f"files joshuac did not write: {_shown(found.foreign)}")
    if found.changed:
        reasons.append(f"generated files edited since the last build: {_shown(found.changed)}")
    if reasons:
        return (
            f"refusing to replace {out}, which holds "
            + "; and ".join(reasons)
            + ". Move them out of the output directory (or delete them) and build again"
        ), found
    return None, found


def lock_directory(path: Path) -> int | None:
    """An open descriptor holding an exclusive flock on a directory, or None when another process holds it."""
    fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    return fd


def _staging_pattern(out: Path) -> re.Pattern:
    return re.compile(re.escape(f".{out.name}.") + r"(old\.)?[A-Za-z0-9_]{8}")


def _is_stale_staging(path: Path) -> bool:
    """An unlocked directory holding nothing but files named in its own stamp (or nothing at all)."""
    listed = read_stamp(path) or {}
    for name, status in _entries(path):
        if stat.S_ISDIR(status.st_mode):
            continue
        if name not in (STAMP, SIGNATURE) and name not in listed:
            return False
    return True


def remove_stale_staging(out: Path) -> None:
    """Remove the staging directories of `out` that killed builds left behind (never anyone else's)."""
    pattern = _staging_pattern(out)
    try:
        candidates = sorted(out.parent.iterdir())
    except OSError:
        return
    for path in candidates:
        if not pattern.fullmatch(path.name) or path.is_symlink() or not path.is_dir():
            continue
        try:
            if path.lstat().st_uid != os.getuid():
                continue
            fd = lock_directory(path)
        except OSError:
            continue
        if fd is None:  # a build at work right now
            continue
        try:
            if _is_stale_staging(path):
                shutil.rmtree(path, ignore_errors=True)
        except OSError:  # emptied under our eyes: the build that replaced it is removing the old tree
            pass
        finally:
            os.close(fd)
