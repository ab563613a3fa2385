"""Write rendered files to an output directory atomically, and compare a directory with them.

The only module of the compiler that touches the disk for output.
"""

import difflib
import fcntl
import os
import posixpath
import re
import shutil
import stat
import tempfile
from dataclasses import dataclass
from pathlib import Path

from joshua_codegen.ownership import (
    SIGNATURE,
    STAMP,
    Survey,
    content_bytes,
    content_digest,
    inspect_output,
    remove_stale_staging,
    stamp_text,
)
from joshua_codegen.render import HOSTS_DIR, host_path, is_executable
from joshua_codegen.version import VERSION
from joshua_core.atomic import exchange_directories


class OutputError(Exception):
    """The output directory cannot be written (or is not ours to replace)."""


def _file_mode(path: str) -> int:
    return 0o755 if is_executable(path) else 0o644


def stamped(files: dict[str, str | bytes], signer=None) -> dict[str, str | bytes]:
    """The files a build writes: the rendered ones and the stamp that proves joshuac wrote them. Each host's
    output of a robot on several hosts gets its own stamp too, since it is deployed (and its install.sh
    checks it) on its own; the stamp of OUT lists those stamps as well. With `signer(bytes) -> bytes`, every
    stamp gets its signature beside it (SIGNATURE), those of the hosts listed in the stamp of OUT."""
    files = dict(files)
    for host in sorted({path.split("/")[1] for path in files if path.startswith(f"{HOSTS_DIR}/")}):
        prefix = host_path(host) + "/"
        part = {path[len(prefix) :]: text for path, text in files.items() if path.startswith(prefix)}
        files[prefix + STAMP] = stamp_text(part)
        if signer is not None:
            files[prefix + SIGNATURE] = signer(files[prefix + STAMP].encode("utf-8"))
    written = {**files, STAMP: stamp_text(files)}
    if signer is not None:
        written[SIGNATURE] = signer(written[STAMP].encode("utf-8"))
    return written


def _resolved(out: Path) -> Path:
    """`out` as an absolute path with its parent's links resolved (OUT itself must not be a link)."""
    if out.is_symlink():
        return out.absolute()
    resolved = out.resolve()
    if resolved == resolved.parent:
        raise OutputError(f"{out} is a file system root: choose a directory of its own")
    return resolved


def _staging_directory(out: Path) -> tuple[Path, int]:
    """A fresh, locked staging directory next to `out` (retried when a cleanup took it first)."""
    while True:
        staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
        # Until the lock is held, a concurrent build may take the empty directory for a killed build's.
        try:
            fd = os.open(staging, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
        except FileNotFoundError:
            continue
        fcntl.flock(fd, fcntl.LOCK_EX)
        try:
            if os.stat(staging, follow_symlinks=False).st_ino == os.fstat(fd).st_ino:
                return staging, fd
        except FileNotFoundError:
            pass
        os.close(fd)


def _reusable(previous: Survey | None, files: dict[str, str | bytes]) -> dict[str, int]:
    """{relative path: inode} of the files of the previous build that the new one holds unchanged, which it takes
    over by a hard link: a new file costs the kernel an inode (on ext4, a search past every inode freed in the
    last minutes), a link costs a name. Only regular files of ours, with their mode, that no other name shares."""
    if previous is None:
        return {}
    reusable = {}
    for relative, content in files.items():
        digest, status = previous.unchanged.get(relative, ("", None))
        if (
            status is not None
            and status.st_nlink == 1
            and status.st_uid == os.getuid()
            and stat.S_IMODE(status.st_mode) == _file_mode(relative)
            and digest == content_digest(content)
        ):
            reusable[relative] = status.st_ino
    return reusable


def _linked(relative: str, out: int, staging: int, inode: int) -> bool:
    """Whether `relative` in `staging` is now a hard link to the file of `out` read as `inode` (a concurrent
    build may have replaced it since). On False, it does not exist. Both directories as descriptors."""
    try:
        os.link(relative, relative, src_dir_fd=out, dst_dir_fd=staging, follow_symlinks=False)
    except OSError:
        return False
    try:
        if os.stat(relative, dir_fd=staging, follow_symlinks=False).st_ino == inode:
            return True
    except OSError:
        pass
    os.unlink(relative, dir_fd=staging)
    return False


def _fill(staging: Path, files: dict[str, str | bytes], out: Path, reusable: dict[str, int]) -> None:
    """Put `files` into the empty `staging` directory: the stamp first (it marks the directory ours), each
    file in `reusable` linked from `out`, the others written, with their modes."""
    (staging / STAMP).write_text(files[STAMP], encoding="utf-8", newline="\n")
    os.chmod(staging / STAMP, _file_mode(STAMP))
    directories = {""}
    into = os.open(staging, os.O_RDONLY | os.O_DIRECTORY)
    source = os.open(out, os.O_RDONLY | os.O_DIRECTORY) if reusable else None
    try:
        for relative, text in files.items():
            if relative == STAMP:
                continue
            directory = posixpath.dirname(relative)
            if directory not in directories:
                os.makedirs(staging / directory, exist_ok=True)
                while directory not in directories:
                    directories.add(directory)
                    directory = posixpath.dirname(directory)
            if relative in reusable and _linked(relative, source, into, reusable[relative]):
                continue
            fd = os.open(relative, os.O_WRONLY | os.O_CREAT | os.O_EXCL, _file_mode(relative), dir_fd=into)
            with os.fdopen(fd, "wb") as stream:
                stream.write(content_bytes(text))
            os.chmod(relative, _file_mode(relative), dir_fd=into)  # whatever the umask
    finally:
        os.close(into)
        if source is not None:
            os.close(source)
    for directory in directories:
        os.chmod(staging / directory, 0o755)


def write_tree(files: dict[str, str | bytes], out: Path, signer=None) -> None:
    """Make `out` hold exactly `files` and their stamp (signed by `signer` when given): all of them or, on
    failure, what it held before.

    Refuses (OutputError, nothing touched) when `out` holds anything joshuac did not write.
    """
    given = Path(out)
    out = _resolved(given)
    reason, previous = inspect_output(out, given)
    if reason is not None:
        raise OutputError(reason)
    files = stamped(files, signer)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_staging(out)
        staging, lock = _staging_directory(out)
    except OSError as exc:
        raise OutputError(f"cannot create a directory next to {out}: {exc.strerror or exc}") from exc
    try:
        _fill(staging, files, out, _reusable(previous, files))
        if out.is_dir() and exchange_directories(staging, out):
            # staging now holds the previous output, which a concurrent build may be removing too
            shutil.rmtree(staging, ignore_errors=True)
            return
        if out.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=out.parent))
            os.rename(out, old)  # onto the empty directory
            os.rename(staging, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.rename(staging, out)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise OutputError(f"cannot write {out}: {exc.strerror or exc}") from exc
    finally:
        os.close(lock)


def replace_file(path: Path, text: str) -> None:
    """Replace a file's content in one step (a temporary file renamed over it), keeping its mode;
    a symbolic link keeps pointing at the file it names, which is the one replaced."""
    target = Path(os.path.realpath(path))
    try:
        mode = stat.S_IMODE(target.stat().st_mode)
        fd, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
        os.chmod(temporary, mode)
        os.replace(temporary, target)
    except OSError as exc:
        os.unlink(temporary)
        raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from exc


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


# The header every generated file starts with names the joshuac that wrote it; a tree written by another
# version holds the same files when nothing else differs, so the comparison reads the header with this one's.
_HEADER_VERSION = re.compile(r"(Generated by joshuac )(\S+)( from )")


@dataclass
class TreeDifference:
    """What `out` lacks or holds beyond the build: a unified diff, and each differing file with how it differs."""

    text: str
    files: list[tuple[str, str]]  # (relative path, "changed" | "missing" | "not generated" | "mode")

    def __bool__(self) -> bool:
        return bool(self.files)

    def summary(self) -> str:
        """`2 files differ: a (changed), b (missing)`."""
        count = len(self.files)
        listed = ", ".join(f"{path} ({how})" for path, how in self.files)
        return f"{count} file{'s' if count != 1 else ''} differ{'s' if count == 1 else ''}: {listed}"


def _as_current(text: str) -> str:
    return _HEADER_VERSION.sub(rf"\g<1>{VERSION}\g<3>", text, count=1)


def diff_tree(files: dict[str, str | bytes], out: Path) -> TreeDifference:
    """How `out` differs from what it should hold, the version in the files' headers aside.

    The stamp (and each host's) is compared only for being there: its hashes follow the files, which are
    compared themselves; a signature is not compared."""
    current = read_tree(out)
    chunks, differing = [], []
    stamps = {path for path in stamped(files) if path.rpartition("/")[2] == STAMP}
    if out.is_dir():
        differing += [(path, "missing") for path in sorted(stamps) if path not in current]
    signatures = {path for path in set(files) | set(current) if path.rpartition("/")[2] == SIGNATURE}
    for relative in sorted((set(files) | set(current)) - stamps - signatures):
        want = files.get(relative)
        if isinstance(want, bytes):
            have_bytes = (out / relative).read_bytes() if relative in current else None
            if have_bytes != want:
                chunks.append(f"Binary file {out / relative} differs\n")
                differing.append((relative, "changed" if have_bytes is not None else "missing"))
            continue
        have, mode = current.get(relative, (None, None))
        if relative in current and have is not None:
            have = _as_current(have)
        if relative in current and want is not None and have == want:
            if mode != _file_mode(relative):
                chunks.append(f"mode of {out / relative}: {mode:o} != {_file_mode(relative):o}\n")
                differing.append((relative, "mode"))
            continue
        differing.append(
            (relative, "missing" if relative not in current else "not generated" if want is None else "changed")
        )
        if relative in current and have is None:
            chunks.append(f"Binary or unreadable file {out / relative} differs\n")
            continue
        old_lines = (have or "").splitlines(keepends=True) if relative in current else []
        new_lines = want.splitlines(keepends=True) if want is not None else []
        chunks.extend(
            difflib.unified_diff(
                old_lines,
                new_lines,
                fromfile=f"a/{relative}" if relative in current else "/dev/null",
                tofile=f"b/{relative}" if want is not None else "/dev/null",
            )
        )
    text = "".join(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n" for line in chunks)
    return TreeDifference(text, sorted(differing))
