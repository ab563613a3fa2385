"""release_tool.py: the robot's side of a rollout, run by the generated playbooks from ROOT/bin, where they copy it
with its modules (layout, release_check, starting); standard library and openssl only.

Releases live side by side under ROOT (default /opt/joshua):

    ROOT/releases/<release>/   one release: the files of `OUT/robots/<robot>/` (+ venv/, its Python environment)
    ROOT/current -> releases/<release>    what runs; switched with one rename(2)
    ROOT/previous -> releases/<release>   what ran before; `rollback` swaps the two
    ROOT/run/, ROOT/logs/      the supervisor's pid file, control socket and logs (start method `supervisor`)

<release> is the first 12 hex digits of the SHA-256 of the release's `.joshuac-stamp` (the `build` the
supervisor reports). A release is checked before anything of it runs: its stamp must be the one named,
signed by the robot's key when the robot has one (`openssl pkeyutl -verify`, Ed25519), list every file
with its SHA-256, and nothing else may be in it. `current` points at a complete, checked release at
every moment: switching stops the robot, renames the link, and starts it again.

Every command prints what it did on its last line; on failure that line is the one-line reason and
the exit code is 1.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tarfile

from layout import ENVIRONMENT_DIR, INCOMING, Refused, linked_release, paths, point
from release_check import check_release, safe_members
from starting import start, start_unless_running, stop

INSTALL_TIMEOUT_S = 3600.0  # install.sh downloads the release's dependencies
SPACE_MARGIN_BYTES = 16 * 1024 * 1024
SPACE_FACTOR = 2  # the archive and its unpacked files are both on disk for a moment


def prepare(args) -> str:
    """Make ROOT's directories and check that the release fits on its file system."""
    layout = paths(args.root)
    for name in ("releases", "run", "logs", "tmp"):
        os.makedirs(layout[name], mode=0o700 if name in ("run", "tmp") else 0o755, exist_ok=True)
    os.chmod(layout["run"], 0o700)
    status = os.statvfs(layout["releases"])
    free = status.f_bavail * status.f_frsize
    needed = args.archive_bytes * SPACE_FACTOR + SPACE_MARGIN_BYTES
    if free < needed:
        raise Refused(
            f"{layout['releases']} has {free / 2**20:.1f} MiB free, the release needs {needed / 2**20:.1f} MiB"
        )
    return json.dumps({"current": linked_release(layout["current"]), "previous": linked_release(layout["previous"])})


def unpack(args) -> str:
    """Unpack the sent archive into releases/.incoming-<release> (nothing when the release is there already)."""
    layout = paths(args.root)
    final = os.path.join(layout["releases"], args.release)
    try:
        if os.path.isdir(final):
            return f"release {args.release} is on the robot already"
        incoming = os.path.join(layout["releases"], INCOMING + args.release)
        shutil.rmtree(incoming, ignore_errors=True)
        os.makedirs(incoming, mode=0o755)
        with tarfile.open(args.archive) as archive:
            archive.extractall(incoming, members=safe_members(archive), numeric_owner=True)
        return f"release {args.release} unpacked"
    except (OSError, tarfile.TarError) as exc:
        raise Refused(f"cannot unpack the release: {exc}") from None
    finally:
        if os.path.exists(args.archive):
            os.unlink(args.archive)


def verify(args) -> str:
    """Check the unpacked (or present) release; an unpacked one becomes releases/<release> only when it passes."""
    layout = paths(args.root)
    incoming = os.path.join(layout["releases"], INCOMING + args.release)
    directory = incoming if os.path.isdir(incoming) else os.path.join(layout["releases"], args.release)
    try:
        check_release(directory, args.release, args.key)
    except Refused:
        shutil.rmtree(incoming, ignore_errors=True)
        raise
    except (OSError, UnicodeDecodeError, subprocess.TimeoutExpired) as exc:
        shutil.rmtree(incoming, ignore_errors=True)
        raise Refused(f"cannot check the release: {exc}") from None
    if directory == incoming:
        os.rename(incoming, os.path.join(layout["releases"], args.release))
    signed = "signature and " if os.path.exists(args.key) else ""
    return f"release {args.release}: {signed}every file checked"


def install(args) -> str:
    """Make the release's Python environment (releases/<release>/venv) with its install.sh."""
    directory = os.path.join(paths(args.root)["releases"], args.release)
    command = ["sh", os.path.join(directory, "install.sh"), os.path.join(directory, ENVIRONMENT_DIR)]
    environment = dict(os.environ, JOSHUA_RELEASE_KEY=args.key)  # install.sh checks the signature against it too
    done = subprocess.run(command, capture_output=True, text=True, timeout=INSTALL_TIMEOUT_S, env=environment)
    lines = (done.stdout + done.stderr).strip().splitlines()
    if done.returncode != 0:
        raise Refused(lines[-1] if lines else f"install.sh exited {done.returncode}")
    return lines[-1] if lines else "installed"


def switch(args) -> str:
    """Stop the robot, point `current` at the release (`previous` at what it was), start the robot."""
    layout = paths(args.root)
    running = linked_release(layout["current"])
    if running == args.release:
        return f"release {args.release} is current already"
    if not os.path.isdir(os.path.join(layout["releases"], args.release)):
        raise Refused(f"release {args.release} is not on the robot")
    stop(args, layout)
    if running is not None:
        point(layout["previous"], running)
    point(layout["current"], args.release)
    start(args, layout)
    return f"switched from {running or 'nothing'} to {args.release}"


def go_back(args, layout: dict, release: str, previous: str | None) -> None:
    """Stop the robot, point `current` at `release` and `previous` at `previous` (or nowhere), start it."""
    stop(args, layout)
    point(layout["current"], release)
    if previous and previous != release and os.path.isdir(os.path.join(layout["releases"], previous)):
        point(layout["previous"], previous)
    elif os.path.lexists(layout["previous"]):
        os.unlink(layout["previous"])
    start(args, layout)


def rollback(args) -> str:
    """Go back to the release `previous` names; `previous` then names the release left."""
    layout = paths(args.root)
    current, previous = linked_release(layout["current"]), linked_release(layout["previous"])
    if previous is None:
        raise Refused("there is no previous release to go back to")
    go_back(args, layout, previous, current)
    return f"rolled back from {current or 'nothing'} to {previous}"


def recover(args) -> str:
    """After a failed switch or gate: `current` and `previous` as before the rollout (`--current-before`,
    `--previous-before`, as `prepare` printed them), the robot started on it; without a release before,
    the robot is stopped."""
    layout = paths(args.root)
    current = linked_release(layout["current"])
    before = args.current_before or None
    if current == before or before == args.release:
        if before is not None:
            start_unless_running(args, layout)
        return f"release {before or 'none'} is current as before"
    if before is None:
        stop(args, layout)
        return f"no release ran before {args.release}: the robot is stopped"
    go_back(args, layout, before, args.previous_before or None)
    return f"rolled back from {args.release} to {before}"


def prune(args) -> str:
    """Remove the releases other than current and previous, and what interrupted transfers left."""
    layout = paths(args.root)
    kept = {linked_release(layout["current"]), linked_release(layout["previous"])} - {None}
    removed = []
    for name in sorted(os.listdir(layout["releases"])):
        if name not in kept:
            shutil.rmtree(os.path.join(layout["releases"], name), ignore_errors=True)
            removed.append(name)
    return f"kept {', '.join(sorted(kept)) or 'nothing'}; removed {len(removed)}"


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="release_tool.py", description=__doc__.splitlines()[0])
    parser.add_argument("--root", default="/opt/joshua")
    commands = parser.add_subparsers(dest="command", required=True)
    command = commands.add_parser("prepare")
    command.add_argument("--archive-bytes", type=int, required=True)
    command = commands.add_parser("unpack")
    command.add_argument("release")
    command.add_argument("archive")
    command = commands.add_parser("verify")
    command.add_argument("release")
    command.add_argument("--key", required=True, help="public key file; when it exists, the release must be signed")
    command = commands.add_parser("install")
    command.add_argument("release")
    command.add_argument("--key", required=True)
    for name in ("switch", "rollback", "recover"):
        command = commands.add_parser(name)
        if name in ("switch", "recover"):
            command.add_argument("release")
        if name == "recover":
            command.add_argument("--current-before", default="", help="the release current named before ('' for none)")
            command.add_argument("--previous-before", default="", help="the release previous named before")
        command.add_argument("--robot", required=True)
        command.add_argument("--control", default="", help="names the control socket (default: the robot)")
        command.add_argument("--start", choices=("systemd", "supervisor"), required=True)
        command.add_argument("--python", default="python3", help="interpreter of the robot's nodes")
        command.add_argument("--unit-dir", default="/etc/systemd/system")
    commands.add_parser("prune")
    return parser.parse_args(argv)


COMMANDS = {
    "prepare": prepare,
    "unpack": unpack,
    "verify": verify,
    "install": install,
    "switch": switch,
    "rollback": rollback,
    "recover": recover,
    "prune": prune,
}


def main(argv=None) -> int:
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        print(COMMANDS[args.command](args), flush=True)
    except Refused as exc:
        print(exc, flush=True)
        return 1
    except (OSError, subprocess.SubprocessError) as exc:
        print(f"{args.command} failed: {exc}", flush=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
