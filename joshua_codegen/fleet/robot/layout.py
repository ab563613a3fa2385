"""Where releases live on a robot (ROOT/releases, current, previous, run, logs) and how a link is switched.

Shipped with the rollout's other robot-side scripts into ROOT/bin (standard library only).
"""

import os
import subprocess

STAMP = ".joshuac-stamp"
SIGNATURE = ".joshuac-stamp.sig"
ENVIRONMENT_DIR = "venv"  # the release's Python environment, made on the robot by install.sh
RELEASE_DIGITS = 12
INCOMING = ".incoming-"
COMMAND_TIMEOUT_S = 120.0  # one systemctl or openssl call


class Refused(Exception):
    """The one-line reason a step cannot go on."""


def paths(root: str) -> dict:
    return {
        "releases": os.path.join(root, "releases"),
        "current": os.path.join(root, "current"),
        "previous": os.path.join(root, "previous"),
        "run": os.path.join(root, "run"),
        "logs": os.path.join(root, "logs"),
        "tmp": os.path.join(root, "tmp"),
    }


def linked_release(link: str) -> str | None:
    """The release a link points at, or None when it is absent or dangling."""
    if not os.path.islink(link) or not os.path.isdir(link):
        return None
    return os.path.basename(os.readlink(link).rstrip("/"))


def point(link: str, release: str) -> None:
    """Make `link` point at releases/<release> in one step (a new link renamed over the old one)."""
    temporary = f"{link}.new"
    if os.path.lexists(temporary):
        os.unlink(temporary)
    os.symlink(os.path.join("releases", release), temporary)
    os.rename(temporary, link)
    directory = os.open(os.path.dirname(link), os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(directory)
    finally:
        os.close(directory)


def run(command: list[str], what: str) -> None:
    done = subprocess.run(command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        raise Refused(f"{what} failed: {lines[-1] if lines else f'exit code {done.returncode}'}")
