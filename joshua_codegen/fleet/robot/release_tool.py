"""joshua-release.py: the robot's side of a rollout, run by the generated playbooks (standard library and openssl only).

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
import hashlib
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import tarfile
import time

STAMP = ".joshuac-stamp"
SIGNATURE = ".joshuac-stamp.sig"
ENVIRONMENT_DIR = "venv"  # the release's Python environment, made on the robot by install.sh
RELEASE_DIGITS = 12
INCOMING = ".incoming-"
STOP_TIMEOUT_S = 60.0  # the supervisor's SIGINT -> SIGTERM -> SIGKILL cascade ends well within this
STOP_POLL_S = 0.1
COMMAND_TIMEOUT_S = 120.0  # one systemctl or openssl call
INSTALL_TIMEOUT_S = 3600.0  # install.sh downloads the release's dependencies
SPACE_MARGIN_BYTES = 16 * 1024 * 1024
SPACE_FACTOR = 2  # the archive and its unpacked files are both on disk for a moment


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


def safe_members(archive: tarfile.TarFile) -> list[tarfile.TarInfo]:
    """The archive's members when every one is a regular file or directory inside it, else Refused."""
    members = archive.getmembers()
    for member in members:
        name = member.name
        parts = [part for part in name.split("/") if part not in ("", ".")]
        if name.startswith("/") or ".." in parts or not (member.isfile() or member.isdir()):
            raise Refused(f"the release archive holds {name!r}, which is not a file or directory inside it")
        member.mode = 0o755 if member.isdir() or member.mode & 0o111 else 0o644
        member.uid = member.gid = 0
        member.uname = member.gname = ""
    return members


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


def file_hash(path: str) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def read_stamp(directory: str) -> dict[str, str]:
    """{path: sha256} of a release's stamp (sha256sum's format after `#` comment lines)."""
    listed = {}
    with open(os.path.join(directory, STAMP), encoding="utf-8") as stamp:
        for line in stamp:
            line = line.rstrip("\n")
            if line.startswith("#") or not line:
                continue
            digest, separator, name = line.partition("  ")
            if not separator or len(digest) != 64:
                raise Refused(f"{STAMP} has a line that is not `SHA256  PATH`")
            listed[name] = digest
    return listed


def check_signature(directory: str, key: str) -> None:
    signature = os.path.join(directory, SIGNATURE)
    if not os.path.isfile(signature):
        raise Refused(
            f"the release is not signed ({SIGNATURE} is missing) and this robot requires signed releases ({key})"
        )
    if shutil.which("openssl") is None:
        raise Refused("openssl is needed to check the release's signature and is not installed")
    command = ["openssl", "pkeyutl", "-verify", "-pubin", "-inkey", key, "-rawin"]
    command += ["-in", os.path.join(directory, STAMP), "-sigfile", signature]
    done = subprocess.run(command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if done.returncode != 0:
        raise Refused(
            f"the signature {SIGNATURE} does not match {STAMP} for the key {key}: the stamp was changed or signed by another key"
        )


def check_release(directory: str, release: str, key: str) -> None:
    """Refused, naming the file, unless `directory` holds exactly the files its stamp lists, unchanged."""
    if not os.path.isfile(os.path.join(directory, STAMP)):
        raise Refused(f"the release has no {STAMP}")
    if file_hash(os.path.join(directory, STAMP))[:RELEASE_DIGITS] != release:
        raise Refused(f"{STAMP} is not the stamp of release {release}")
    if os.path.exists(key):
        check_signature(directory, key)
    listed = read_stamp(directory)
    for name, digest in sorted(listed.items()):
        path = os.path.join(directory, name)
        if os.path.islink(path) or not os.path.isfile(path):
            raise Refused(f"{name} is missing from the release")
        if file_hash(path) != digest:
            raise Refused(f"{name} differs from the release's {STAMP}" + (" (signed)" if os.path.exists(key) else ""))
    parents = set()
    for name in listed:
        parent = os.path.dirname(name)
        while parent:
            parents.add(parent)
            parent = os.path.dirname(parent)
    for base, directories, files in os.walk(directory):
        relative = os.path.relpath(base, directory)
        if relative == ".":
            directories[:] = [name for name in directories if name != ENVIRONMENT_DIR]
        for name in sorted(directories + files):
            entry = os.path.normpath(os.path.join(relative, name))
            mode = os.lstat(os.path.join(base, name)).st_mode
            if stat.S_ISDIR(mode) and entry in parents:
                continue
            if entry not in listed and entry not in (STAMP, SIGNATURE):
                raise Refused(f"{entry} is not part of the release (not in its {STAMP})")


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


def supervisor_pid(layout: dict) -> int | None:
    """The running supervisor's pid from run/supervisor.pid, when that process is a supervisor.py."""
    try:
        with open(os.path.join(layout["run"], "supervisor.pid"), encoding="ascii") as file:
            pid = int(file.read().strip())
        with open(f"/proc/{pid}/cmdline", "rb") as file:
            return pid if b"supervisor.py" in file.read() else None
    except (OSError, ValueError):
        return None


def stop(args, layout: dict) -> None:
    if args.start == "systemd":
        target = f"joshua-{args.robot}.target"
        run(["systemctl", "stop", target], f"systemctl stop {target}")
        return
    pid = supervisor_pid(layout)
    if pid is None:
        return
    os.kill(pid, signal.SIGTERM)
    deadline = time.monotonic() + STOP_TIMEOUT_S
    while os.path.exists(f"/proc/{pid}") and supervisor_pid(layout) == pid:
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            break
        time.sleep(STOP_POLL_S)


def run(command: list[str], what: str) -> None:
    done = subprocess.run(command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        raise Refused(f"{what} failed: {lines[-1] if lines else f'exit code {done.returncode}'}")


def install_units(args, layout: dict) -> None:
    """The current release's units in /etc/systemd/system (this robot's older ones removed), enabled."""
    units_dir = os.path.join(layout["current"], "systemd")
    wanted = sorted(os.listdir(units_dir))
    prefix = f"joshua-{args.robot}"
    for name in os.listdir(args.unit_dir):
        if (name == f"{prefix}.target" or name.startswith(f"{prefix}-")) and name not in wanted:
            os.unlink(os.path.join(args.unit_dir, name))
    for name in wanted:
        shutil.copyfile(os.path.join(units_dir, name), os.path.join(args.unit_dir, name))
    run(["systemctl", "daemon-reload"], "systemctl daemon-reload")
    run(["systemctl", "enable", f"{prefix}.target"], f"systemctl enable {prefix}.target")


def start(args, layout: dict) -> None:
    if args.start == "systemd":
        install_units(args, layout)
        run(["systemctl", "start", f"joshua-{args.robot}.target"], f"systemctl start joshua-{args.robot}.target")
        return
    command = [args.python, os.path.join(layout["current"], "supervisor.py")]
    command += ["--control-socket", os.path.join(layout["run"], f"{args.control or args.robot}.sock")]
    command += ["--log-dir", layout["logs"]]
    with open(os.path.join(layout["logs"], "supervisor.log"), "ab") as log:
        process = subprocess.Popen(
            command, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, start_new_session=True
        )
    with open(os.path.join(layout["run"], "supervisor.pid"), "w", encoding="ascii") as file:
        file.write(f"{process.pid}\n")


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


def start_unless_running(args, layout: dict) -> None:
    if args.start == "supervisor" and supervisor_pid(layout) is not None:
        return
    start(args, layout)


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
    parser = argparse.ArgumentParser(prog="joshua-release.py", description=__doc__.splitlines()[0])
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
