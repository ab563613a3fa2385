"""The workspace's wheels as last built from each state of their sources, kept in the user's cache directory.

Building the two wheels takes uv about 2 s, most of `build --bundle` and `build --image`. Hatchling builds
them reproducibly, so the wheels of sources that have not changed are the wheels already built: they are
kept under a digest of everything they are made of (`sources_digest`). Keeping is best effort: where the
cache directory cannot be written, every build builds.
"""

import hashlib
import os
import shutil
import tempfile
import time
from pathlib import Path

CACHE_DIR = "joshua/wheels"  # under $XDG_CACHE_HOME, else ~/.cache
KEPT = 4  # states of the sources whose wheels are kept; adding one removes the oldest beyond these
WHEEL_SUFFIX = ".whl"
ABANDONED_AFTER_S = 3600.0  # a half-written entry (a build that died while keeping it) is removed after this


def cache_root() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / CACHE_DIR


def sources_digest(members: list[Path]) -> str:
    """A digest of everything the members' wheels can be made of: every file of each member's directory (its
    pyproject.toml, a README, its packages, and more, such as tests, that only make the digest change more
    often), bytecode aside, with their executable bits."""
    digest = hashlib.sha256()
    for member in members:
        files = sorted(path for path in member.rglob("*") if path.is_file() and "__pycache__" not in path.parts)
        for path in files:
            data = path.read_bytes()
            executable = path.stat().st_mode & 0o111
            digest.update(f"{path.relative_to(member.parent)}\0{executable:o}\0{len(data)}\0".encode())
            digest.update(data)
    return digest.hexdigest()[:32]


def load(digest: str) -> dict[str, bytes] | None:
    """{wheel file name: content} kept for `digest`, or None."""
    entry = cache_root() / digest
    try:
        wheels = {path.name: path.read_bytes() for path in sorted(entry.glob(f"*{WHEEL_SUFFIX}"))}
        if wheels:
            os.utime(entry)  # used now: the last to be removed
    except OSError:
        return None
    return wheels or None


def store(digest: str, wheels: dict[str, bytes]) -> None:
    """Keep `wheels` for `digest`: written beside the entry and renamed into place, so a reader never sees
    half of them; then only the KEPT newest entries stay, and no half-written one of a build long gone."""
    root = cache_root()
    staging_since = time.time() - ABANDONED_AFTER_S
    try:
        root.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{digest}-", dir=root))
        for name, data in wheels.items():
            (staging / name).write_bytes(data)
        try:
            staging.rename(root / digest)
        except OSError:  # another build kept the same wheels meanwhile
            shutil.rmtree(staging, ignore_errors=True)
        entries = sorted(root.iterdir(), key=lambda path: path.stat().st_mtime)
        kept = [path for path in entries if not path.name.startswith(".")]
        abandoned = [path for path in entries if path.name.startswith(".") and path.stat().st_mtime < staging_since]
        for old in [*kept[:-KEPT], *abandoned]:
            shutil.rmtree(old, ignore_errors=True)
    except OSError:
        return
