"""Write rendered files to an output directory atomically, and compare a directory with them.

The only module of the compiler that touches the disk for output.
"""

import difflib
import os
import shutil
import tempfile
from pathlib import Path

from joshua_core.atomic import exchange_directories
from joshua_codegen.render import is_executable

MARKER = "manifest.json"  # an output directory joshuac may replace always holds this file


class OutputError(Exception):
    """The output directory cannot be written (or is not ours to replace)."""


def _file_mode(path: str) -> int:
    return 0o755 if is_executable(path) else 0o644


def _check_replaceable(out: Path) -> None:
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise OutputError(f"{out} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).is_file():
        raise OutputError(f"{out} is not empty and holds no {MARKER}: refusing to replace a directory joshuac did not write")


def write_tree(files: dict[str, str], out: Path) -> None:
    """Make `out` hold exactly `files`: all of them or, on failure, what it held before."""
    out = Path(out)
    _check_replaceable(out)
    parent = out.parent if str(out.parent) else Path(".")
    try:
        parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=parent))
    except OSError as exc:
        raise OutputError(f"cannot create {parent}: {exc.strerror}") from exc
    try:
        for relative, text in files.items():
            target = staging / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8", newline="\n")
            os.chmod(target, _file_mode(relative))
        for directory in [staging, *(p for p in staging.rglob("*") if p.is_dir())]:
            os.chmod(directory, 0o755)
        if out.is_dir() and exchange_directories(staging, out):
            shutil.rmtree(staging)  # now holds the previous output
            return
        if out.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=parent))
            os.rename(out, old / "tree")
            os.rename(staging, out)
            shutil.rmtree(old)
        else:
            os.rename(staging, out)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise OutputError(f"cannot write {out}: {exc.strerror or exc}") from exc


def read_tree(out: Path) -> dict[str, tuple[str | None, int]]:
    """Every file under `out` as {relative path: (text or None when not UTF-8, mode)}."""
    tree = {}
    out = Path(out)
    if not out.is_dir():
        return tree
    for path in sorted(p for p in out.rglob("*") if p.is_file() or p.is_symlink()):
        relative = path.relative_to(out).as_posix()
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            text = None
        tree[relative] = (text, path.lstat().st_mode & 0o777)
    return tree


def diff_tree(files: dict[str, str], out: Path) -> str:
    """A unified diff from what `out` holds to what it should hold ("" when identical)."""
    current = read_tree(out)
    chunks = []
    for relative in sorted(set(files) | set(current)):
        want = files.get(relative)
        have, mode = current.get(relative, (None, None))
        if relative in current and want is not None and have == want:
            if mode != _file_mode(relative):
                chunks.append(f"mode of {out / relative}: {mode:o} != {_file_mode(relative):o}\n")
            continue
        old_lines = (have or "").splitlines(keepends=True) if relative in current else []
        new_lines = want.splitlines(keepends=True) if want is not None else []
        if relative in current and have is None:
            chunks.append(f"Binary or unreadable file {out / relative} differs\n")
            continue
        chunks.extend(difflib.unified_diff(
            old_lines, new_lines,
            fromfile=f"a/{relative}" if relative in current else "/dev/null",
            tofile=f"b/{relative}" if want is not None else "/dev/null",
        ))
    return "".join(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n" for line in chunks)
