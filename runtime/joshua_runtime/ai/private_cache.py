"""A process's private directory in /tmp that outlives no crash for long: held under a lock while the process
lives, and removed by the next process that makes one once the lock is free (the kernel frees it when its
holder dies, SIGKILL included; a lock, unlike a pid, says so across pid namespaces sharing one /tmp)."""

import fcntl
import os
import shutil
import tempfile
import time
from pathlib import Path

LOCK_NAME = ".owner.lock"
UNLOCKED_AFTER_S = 3600.0  # a directory without a lock file (made before locks were) is removed after this


def make(prefix: str) -> tuple[str, int]:
    """A new directory named `prefix`*, and the descriptor whose lock holds it (closed by `remove`), once those
    whose holder is gone are removed."""
    remove_abandoned(prefix)
    directory = tempfile.mkdtemp(prefix=prefix)
    staged = os.path.join(directory, LOCK_NAME + ".new")
    lock = os.open(staged, os.O_CREAT | os.O_WRONLY | os.O_CLOEXEC, 0o600)
    fcntl.flock(lock, fcntl.LOCK_EX)
    os.rename(staged, os.path.join(directory, LOCK_NAME))  # only ever seen locked under its name
    return directory, lock


def remove(directory: str, lock: int) -> None:
    shutil.rmtree(directory, ignore_errors=True)
    os.close(lock)


def remove_abandoned(prefix: str) -> None:
    """Remove the directories named `prefix`* whose lock no process holds."""
    unlocked_before = time.time() - UNLOCKED_AFTER_S
    for directory in Path(tempfile.gettempdir()).glob(f"{prefix}*"):
        try:
            lock = os.open(directory / LOCK_NAME, os.O_RDONLY | os.O_CLOEXEC)
        except FileNotFoundError:
            try:
                if directory.is_dir() and directory.stat().st_mtime < unlocked_before:
                    shutil.rmtree(directory, ignore_errors=True)
            except OSError:
                pass
            continue
        except OSError:
            continue
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            continue  # held: its process lives
        finally:
            os.close(lock)
        shutil.rmtree(directory, ignore_errors=True)
