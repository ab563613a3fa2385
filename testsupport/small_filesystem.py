"""A small tmpfs mounted for one test (tests run as root), to meet a real full disk (ENOSPC)."""

import contextlib
import errno
import os
import subprocess
from pathlib import Path

FILL_CHUNK_BYTES = 64 * 1024


@contextlib.contextmanager
def small_filesystem(directory: Path, size: str = "2m"):
    """Mount a tmpfs of `size` at `directory` (created), yield it, and unmount it afterwards."""
    directory.mkdir(parents=True, exist_ok=True)
    subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(directory)], check=True)
    try:
        yield directory
    finally:
        subprocess.run(["umount", "--lazy", str(directory)], check=True)


def fill(directory: Path) -> Path:
    """Write a file in `directory` until its filesystem has no byte left; returns the file."""
    filler = directory / "filler"
    fd = os.open(filler, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    try:
        size = FILL_CHUNK_BYTES
        while size:
            try:
                os.write(fd, b"\0" * size)
            except OSError as exc:
                if exc.errno != errno.ENOSPC:
                    raise
                size //= 2
    finally:
        os.close(fd)
    return filler
