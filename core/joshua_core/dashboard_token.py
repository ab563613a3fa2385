"""The dashboard's access token: one secret per robot in a file only its owner can read, next to the
supervisor's control socket (`ROBOT.sock` -> `ROBOT.dashboard-token`).

`joshuac run` creates it before the robot starts and prints the page's address with it; the dashboard
process reads it (or creates it, under systemd or supervisord). It never travels through a command
line, an environment variable or a log. Deleting the file makes the next start choose a new token.
"""

import os
import re
import secrets
import stat
from pathlib import Path

TOKEN_SUFFIX = ".dashboard-token"
TOKEN_BYTES = 32  # 43 URL-safe characters
MIN_TOKEN_CHARS = 16  # a token written by hand must still be hard to guess
MAX_TOKEN_FILE_BYTES = 4096
# URL-safe, so that the token goes into the page's address unchanged.
_TOKEN = re.compile(r"^[A-Za-z0-9._~-]+$")
_OTHERS_MAY_WRITE = stat.S_IWGRP | stat.S_IWOTH
_OTHERS_MAY_ACCESS = stat.S_IRWXG | stat.S_IRWXO


class TokenFileError(Exception):
    """The token file cannot be created or is not safe to use (the message is one line)."""


def token_path(control_socket: Path) -> Path:
    """Where the token of the robot whose supervisor serves `control_socket` lives."""
    control_socket = Path(control_socket)
    return control_socket.with_name(control_socket.stem + TOKEN_SUFFIX)


def load_or_create_token(path: Path) -> str:
    """The token in `path`; a new random one written there (mode 0600) when the file is absent.

    The directory is created with mode 0700 when missing; an existing one must belong to this user
    and be writable by nobody else, and the file must belong to this user and be readable by nobody
    else; otherwise TokenFileError (someone else could know or swap the token)."""
    path = Path(path)
    _private_directory(path.parent)
    try:
        return _read(path)
    except FileNotFoundError:
        pass
    token = secrets.token_urlsafe(TOKEN_BYTES)
    draft = path.with_name(f".{path.name}.{secrets.token_hex(8)}")
    try:
        descriptor = os.open(draft, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        with os.fdopen(descriptor, "w") as draft_file:
            draft_file.write(token + "\n")
        os.link(draft, path)  # fails when another process created the file meanwhile: its token wins
    except FileExistsError:
        return _read(path)
    except OSError as exc:
        raise TokenFileError(f"cannot create the dashboard token file {path}: {exc.strerror or exc}") from exc
    finally:
        draft.unlink(missing_ok=True)
    return token


def _private_directory(directory: Path) -> None:
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = os.lstat(directory)
    except OSError as exc:
        raise TokenFileError(f"cannot create the directory {directory}: {exc.strerror or exc}") from exc
    if not stat.S_ISDIR(info.st_mode) or info.st_uid != os.geteuid() or info.st_mode & _OTHERS_MAY_WRITE:
        raise TokenFileError(
            f"{directory} must be a directory of user {os.geteuid()} that no one else may write to "
            f"(it is mode {stat.filemode(info.st_mode)}, owner {info.st_uid})"
        )


def _read(path: Path) -> str:
    """The token of an existing file, after checking who may read it (FileNotFoundError when absent)."""
    try:
        descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except FileNotFoundError:
        raise
    except OSError as exc:
        raise TokenFileError(f"cannot read the dashboard token file {path}: {exc.strerror or exc}") from exc
    with os.fdopen(descriptor, "rb") as token_file:
        info = os.fstat(token_file.fileno())
        if not stat.S_ISREG(info.st_mode) or info.st_uid != os.geteuid() or info.st_mode & _OTHERS_MAY_ACCESS:
            raise TokenFileError(
                f"the dashboard token file {path} must be a file of user {os.geteuid()} that only it may read "
                f"(it is mode {stat.filemode(info.st_mode)}, owner {info.st_uid}); fix it or delete it"
            )
        text = token_file.read(MAX_TOKEN_FILE_BYTES).decode("ascii", errors="replace").strip()
    if len(text) < MIN_TOKEN_CHARS or not _TOKEN.match(text):
        raise TokenFileError(
            f"the dashboard token file {path} must hold one token of at least {MIN_TOKEN_CHARS} characters "
            "A-Z a-z 0-9 . _ ~ - (delete the file to have one chosen)"
        )
    return text
