"""A build of the robot as data: its directory, its supervisor.py's data (read, never run) and its files' hashes."""

import hashlib
import os
import re

from joshua_codegen.supervisor.common import SCRIPT_DIR
from joshua_codegen.supervisor.robot import ROBOT, SIGINT_GRACE_S, SIGTERM_GRACE_S
from joshua_codegen.supervisor.run_mark import build_stamp

BUILD_SUPERVISOR = "supervisor.py"
# The names supervisor.py holds as plain data (those of the placeholder robot.py): a reload reads their values.
BUILD_DATA_NAMES = ("ROBOT", "SIGINT_GRACE_S", "SIGTERM_GRACE_S")
BUILD_FILE_MAX_BYTES = 64 * 1024 * 1024  # the largest stamp, supervisor.py or node file a reload reads
STAMP_ENTRY = re.compile(r"([0-9a-f]{64})  (.+)")


class BuildError(Exception):
    """Why a directory is not a build a reload can take: one line."""


class Build:
    """One build of the robot: `directory` (its files' paths are relative to it), `robot` (its ROBOT data),
    the stop grace periods, `digest` (the SHA-256 of its stamp, "" when unknown), `built` (the stamp's
    modification time, None when unknown) and `files`: the SHA-256 of each file its processes run from it
    (entrypoints and DDS profiles; None when unreadable)."""

    def __init__(self, directory: str, robot: dict, sigint_grace_s: float, sigterm_grace_s: float, stamp, files):
        self.directory = directory
        self.robot = robot
        self.sigint_grace_s = sigint_grace_s
        self.sigterm_grace_s = sigterm_grace_s
        self.digest, self.built = stamp
        self.files = files

    def path(self, relative: str) -> str:
        """A path of the build as the nodes use it: absolute as it is, else under the build's directory."""
        return relative if os.path.isabs(relative) else os.path.join(self.directory, relative)


def process_files(robot: dict) -> list[str]:
    """The files of a build its processes run: each Python entrypoint and each DDS profile, once."""
    files = []
    for spec in robot["processes"]:
        files += [spec["entrypoint"]] if spec["entrypoint"] else []
        files.append(spec["fastdds_profile"])
    return list(dict.fromkeys(files))


def file_digest(path: str) -> str | None:
    try:
        with open(path, "rb") as handle:
            return hashlib.sha256(handle.read(BUILD_FILE_MAX_BYTES + 1)).hexdigest()
    except OSError:
        return None


def running_build() -> Build:
    """The build this supervisor was started from, its files hashed as they are now."""
    files = {relative: file_digest(os.path.join(SCRIPT_DIR, relative)) for relative in process_files(ROBOT)}
    return Build(SCRIPT_DIR, ROBOT, SIGINT_GRACE_S, SIGTERM_GRACE_S, build_stamp(), files)


def read_bounded(path: str, what: str) -> bytes:
    try:
        with open(path, "rb") as handle:
            data = handle.read(BUILD_FILE_MAX_BYTES + 1)
    except OSError as exc:
        raise BuildError(f"cannot read {what}: {exc.strerror or exc}") from None
    if len(data) > BUILD_FILE_MAX_BYTES:
        raise BuildError(f"{what} is larger than {BUILD_FILE_MAX_BYTES} bytes")
    return data


def stamp_entries(data: bytes) -> dict[str, str] | None:
    """{path: sha256} of a stamp's text (`sha256sum` lines after `#` comments), None when it is not one."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return None
    entries = {}
    for line in text.splitlines():
        if line.startswith("#"):
            continue
        match = STAMP_ENTRY.fullmatch(line)
        if match is None:
            return None
        entries[match.group(2)] = match.group(1)
    return entries


def find_stamp(directory: str) -> tuple[dict[str, str], tuple[str, float]]:
    """(the entries, (the SHA-256, the modification time)) of the stamp beside the build's supervisor.py (one host's part of a robot on
    several hosts, OUT/hosts/NAME, has its own), which must list that file."""
    path = os.path.join(directory, ROBOT["stamp_file"])
    if os.path.isfile(path):
        data = read_bounded(path, ROBOT["stamp_file"])
        entries = stamp_entries(data)
        if entries is not None and BUILD_SUPERVISOR in entries:
            return entries, (hashlib.sha256(data).hexdigest(), os.stat(path).st_mtime)
    raise BuildError(f"no {ROBOT['stamp_file']} lists its {BUILD_SUPERVISOR}: it is not a joshuac build")


def checked_file(directory: str, entries: dict[str, str], relative: str) -> tuple[bytes, str]:
    """(content, sha256) of a build's file, which must be in its stamp with that hash."""
    listed = entries.get(relative)
    if listed is None:
        raise BuildError(f"{relative} is not in the build's {ROBOT['stamp_file']}")
    data = read_bounded(os.path.join(directory, relative), relative)
    digest = hashlib.sha256(data).hexdigest()
    if digest != listed:
        raise BuildError(f"{relative} differs from the build's {ROBOT['stamp_file']} (changed after the build)")
    return data, digest


def build_data(source: bytes) -> dict:
    """The values of BUILD_DATA_NAMES in a supervisor.py, read as literals: nothing in it runs."""
    import ast

    try:
        tree = ast.parse(source, BUILD_SUPERVISOR)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise BuildError(f"{BUILD_SUPERVISOR} is not Python") from None
    values = {}
    for statement in tree.body:
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
            continue
        target = statement.targets[0]
        if isinstance(target, ast.Name) and target.id in BUILD_DATA_NAMES:
            try:
                values[target.id] = ast.literal_eval(statement.value)
            except (ValueError, TypeError, SyntaxError, RecursionError, MemoryError):
                raise BuildError(f"{target.id} in {BUILD_SUPERVISOR} is not plain data") from None
    missing = [name for name in BUILD_DATA_NAMES if name not in values]
    if missing:
        raise BuildError(f"{BUILD_SUPERVISOR} holds no {', '.join(missing)}: not a robot's supervisor")
    return values


def checked_robot(values: dict) -> dict:
    """The ROBOT data, with the shape this supervisor reads: named processes, numbers for the grace periods."""
    robot = values["ROBOT"]
    processes = robot.get("processes") if isinstance(robot, dict) else None
    if not isinstance(processes, list) or not all(isinstance(spec, dict) for spec in processes):
        raise BuildError(f"ROBOT in {BUILD_SUPERVISOR} has no list of processes")
    names = [spec.get("name") for spec in processes]
    if not all(isinstance(name, str) and name for name in names) or len(set(names)) != len(names):
        raise BuildError(f"the processes in {BUILD_SUPERVISOR} are not named one by one")
    for name in BUILD_DATA_NAMES[1:]:
        if type(values[name]) not in (int, float) or not values[name] >= 0:
            raise BuildError(f"{name} in {BUILD_SUPERVISOR} is not a number of seconds")
    return robot


def read_build(path: str) -> Build:
    """The build in directory `path` (symbolic links resolved: the nodes run from the files checked here), its
    supervisor.py and every file its processes run checked against its stamp. Raises BuildError."""
    directory = os.path.realpath(path)
    if not os.path.isdir(directory):
        raise BuildError("not a directory")
    if not os.path.isfile(os.path.join(directory, BUILD_SUPERVISOR)):
        raise BuildError(f"no {BUILD_SUPERVISOR} in it: not a robot's build directory")
    entries, stamp = find_stamp(directory)
    source, _ = checked_file(directory, entries, BUILD_SUPERVISOR)
    values = build_data(source)
    robot = checked_robot(values)
    try:
        relatives = process_files(robot)
    except (KeyError, TypeError):
        raise BuildError(f"the processes in {BUILD_SUPERVISOR} are not of this supervisor's format") from None
    files = {relative: checked_file(directory, entries, relative)[1] for relative in relatives}
    return Build(directory, robot, values["SIGINT_GRACE_S"], values["SIGTERM_GRACE_S"], stamp, files)
