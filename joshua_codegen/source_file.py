"""Read a description file with bounded time and memory: regular files up to MAX_DESCRIPTION_BYTES only.

A FIFO would block forever, a character device (`/dev/urandom`) never ends, and a pseudo file of
/proc or /sys reports a size unrelated to what it yields; all are refused with a diagnostic before
more than MAX_DESCRIPTION_BYTES + 1 bytes are read. The file is opened without blocking and without
becoming a controlling terminal, and the checks are made on the opened descriptor (no race with a
rename in between); the path is looked at first so that a device is not even opened.
"""

from __future__ import annotations

import errno
import os
import stat

from joshua_codegen.diagnostics import ERROR, Diagnostic
from joshua_codegen.load import NOT_REGULAR_FILE, UNREADABLE_FILE

# 1 MiB: the largest description file joshuac reads. A 3000-node description is about 0.3 MiB; checking
# costs up to ~30 s and ~1 GB for a 1 MiB file that is nothing but one list of erroneous items (350k
# diagnostics), so a larger limit would let one file hold a machine for minutes.
MAX_DESCRIPTION_BYTES = 1024 * 1024
_READ_CHUNK = 1024 * 1024
_KINDS = {
    stat.S_IFIFO: "a FIFO (named pipe)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
}


class SourceProblem(Exception):
    """The file cannot be read as a description; `diagnostic` says why."""

    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


def _problem(path: str, code: str, message: str) -> SourceProblem:
    return SourceProblem(Diagnostic(path, 1, 1, code, ERROR, message))


def _refuse_kind(path: str, status: os.stat_result) -> None:
    if stat.S_ISDIR(status.st_mode):
        raise _problem(path, UNREADABLE_FILE, f"cannot read the file: {os.strerror(errno.EISDIR)}")
    if not stat.S_ISREG(status.st_mode):
        kind = _KINDS.get(stat.S_IFMT(status.st_mode), "not a regular file")
        raise _problem(path, NOT_REGULAR_FILE, f"the path is {kind}, not a regular file: give a description file")
    if status.st_size > MAX_DESCRIPTION_BYTES:
        raise _too_large(path, f"{status.st_size} bytes")


def _too_large(path: str, size: str) -> SourceProblem:
    return _problem(
        path,
        NOT_REGULAR_FILE,
        f"the file is too large ({size}); descriptions are limited to {MAX_DESCRIPTION_BYTES} bytes (1 MiB)",
    )


def read_description(path: str) -> bytes:
    """The bytes of a description file; SourceProblem (E007 or E009) when it cannot or may not be read."""
    try:
        _refuse_kind(path, os.stat(path))
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    except (OSError, ValueError) as exc:
        raise _problem(
            path, UNREADABLE_FILE, f"cannot read the file: {getattr(exc, 'strerror', None) or exc}"
        ) from None
    try:
        status = os.fstat(fd)
        _refuse_kind(path, status)
        chunks, total = [], 0
        while total <= MAX_DESCRIPTION_BYTES:
            chunk = os.read(fd, min(_READ_CHUNK, MAX_DESCRIPTION_BYTES + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as exc:
        raise _problem(path, UNREADABLE_FILE, f"cannot read the file: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    if total > MAX_DESCRIPTION_BYTES:
        raise _too_large(path, f"more than {MAX_DESCRIPTION_BYTES} bytes")
    if total != status.st_size:
        raise _problem(
            path,
            NOT_REGULAR_FILE,
            f"the file gave {total} bytes but its size is {status.st_size}: it changed while being read, "
            "or it is a pseudo file (/proc, /sys); copy it to a regular file",
        )
    return b"".join(chunks)
