"""`build --bundle`: the runtime's wheels, its pinned requirements and an install script, as output files.

A robot needs joshua-core and joshua-runtime (with the extras its node types name) for the interpreter
that runs its Python nodes. The bundle holds, next to the build:

    OUT/install.sh               creates a virtual environment and installs the two below into it
    OUT/wheels/*.whl             joshua-core and joshua-runtime, built from this source tree
    OUT/wheels/local-requirements.txt   those two wheels pinned with their SHA-256
    OUT/wheels/requirements.txt  their third-party dependencies pinned with hashes from uv.lock

install.sh installs nothing unless every file of the build matches OUT/.joshuac-stamp and OUT/wheels/
holds no file the build did not write; the installer then checks each wheel against its pinned hash.

Third-party wheels (rclpy and the ROS message packages from PyPI, numpy, OpenCV, LeRobot, MuJoCo) are
not copied: install.sh takes them from PyPI, checked against the hashes; options given to install.sh
after the environment directory reach the installer (`--find-links DIR`, `--index-url URL`).

Building needs this source tree (uv.lock and the workspace members) and uv, a dependency of joshuac.

A robot on several hosts gets one bundle per host, in OUT/hosts/<name>/, each with the extras of that
host's processes only (a Raspberry Pi running the servos does not get torch). A host with
`ros_from_system` takes ROS 2 from apt: its requirements leave the ROS wheels out, its environment is
made with --system-site-packages by the host's `python` (3.10 to 3.12, as the runtime), and install.sh
sources the ROS setup first. Every other host needs Python 3.11 on x86_64, the only platform the ROS wheels
exist for: its install.sh refuses another, where the environment would install (uv.lock covers 3.10 to 3.12,
x86_64 and aarch64) but without rclpy.
"""

import hashlib
import os
import re
import subprocess
import tempfile
from functools import cache
from pathlib import Path

from joshua_codegen import wheel_cache
from joshua_codegen.model import Robot
from joshua_codegen.ownership import STAMP
from joshua_codegen.placement import ROS_SYSTEM_SETUP
from joshua_codegen.render import host_path, template
from joshua_codegen.signing import DEFAULT_RELEASE_KEY
from joshua_core import dashboard
from joshua_core.control_plane import PROCESS_TYPE as HOST_AGENT_TYPE
from joshua_core.node_types import spec
from joshua_core.settings import FORMAT_VERSION

SOURCE_ROOT = Path(__file__).resolve().parent.parent
PACKAGES = {"joshua-core": "core", "joshua-runtime": "runtime"}  # the workspace members the runtime is made of
RUNTIME_PACKAGE = "joshua-runtime"
INSTALL_SCRIPT = "install.sh"
WHEEL_DIR = "wheels"
REQUIREMENTS = f"{WHEEL_DIR}/requirements.txt"
LOCAL_REQUIREMENTS_NAME = "local-requirements.txt"
LOCAL_REQUIREMENTS = f"{WHEEL_DIR}/{LOCAL_REQUIREMENTS_NAME}"
DEFAULT_VENV = "/opt/joshua/venv"
# The ROS 2 wheels on PyPI are CPython 3.11's on x86_64 alone (runtime/pyproject.toml marks them so).
ROS_WHEELS_PYTHON = "3.11"
ROS_WHEELS_MACHINE = "x86_64"  # as platform.machine() names it
PYTHON = f"python{ROS_WHEELS_PYTHON}"  # the interpreter of a host that takes them
UV_TIMEOUT_S = 600.0
ROS_WHEEL_PREFIX = "ros-"  # the ROS 2 packages on PyPI (ros-jazzy-rclpy, ros-rcl, ...), from apt with ros_from_system


class BundleError(Exception):
    """The bundle cannot be made here (no source tree, uv failed)."""


def extras(robot: Robot) -> list[str]:
    """The joshua-runtime extras the robot's processes need, sorted: those of their node types, and the
    dashboard's for the dashboard process and for host agents of a control plane, which speak Zenoh."""
    needed = {spec(p.node_type).runtime_extra for p in robot.processes if spec(p.node_type)}
    agents_talk = robot.control is not None and any(p.node_type == HOST_AGENT_TYPE for p in robot.processes)
    if agents_talk or any(p.node_type == dashboard.PROCESS_TYPE for p in robot.processes):
        needed.add(dashboard.RUNTIME_EXTRA)
    return sorted(needed - {""})


def uv(*arguments: str) -> str:
    """Run uv in the source tree; its standard output."""
    from uv import find_uv_bin

    env = {**os.environ, "UV_PYTHON_DOWNLOADS": "never"}
    try:
        done = subprocess.run(
            [find_uv_bin(), *arguments],
            cwd=SOURCE_ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=UV_TIMEOUT_S,
            stdin=subprocess.DEVNULL,
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise BundleError(f"uv {arguments[0]} failed: {exc}") from exc
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or [f"exit code {done.returncode}"])[-1]
        raise BundleError(f"uv {arguments[0]} failed: {last}")
    return done.stdout


@cache
def wheels() -> dict[str, bytes]:
    """{wheel file name: content} of the workspace packages the runtime is made of (those last built from the
    same sources when the user's cache holds them: `wheel_cache`)."""
    members = [SOURCE_ROOT / member for member in PACKAGES.values()]
    digest = wheel_cache.sources_digest(members)
    kept = wheel_cache.load(digest)
    if kept:
        return kept
    with tempfile.TemporaryDirectory(prefix="joshuac-wheels-") as directory:
        for package in PACKAGES:
            uv("build", "--quiet", "--wheel", "--package", package, "--out-dir", directory)
        built = {path.name: path.read_bytes() for path in sorted(Path(directory).glob("*.whl"))}
    if wheel_cache.sources_digest(members) == digest:  # not kept when a source changed while uv built
        wheel_cache.store(digest, built)
    return built


def requirements(robot: Robot, without_ros: bool = False) -> str:
    """The runtime's third-party dependencies (with the robot's extras), pinned with hashes from uv.lock;
    `without_ros`: the ROS wheels left out."""
    text = _exported(tuple(extras(robot)))
    return _without_ros_wheels(text) if without_ros else text


def _without_ros_wheels(text: str) -> str:
    """An exported requirements file without the ROS wheels and the packages only they need (each entry is a
    line, its indented hashes and its `# via` lines, which name the packages that need it)."""
    entries: list[tuple[str, list[str], list[str]]] = []  # (name, lines, the packages that need it)
    for line in text.splitlines(keepends=True):
        if not line[:1].isspace() and not line.startswith("#"):
            entries.append((re.split(r"[=\s;\[]", line, maxsplit=1)[0].lower(), [line], []))
            continue
        if entries:
            name, lines, needed_by = entries[-1]
            lines.append(line)
            comment = line.strip()
            if comment.startswith("# via"):
                needed_by += comment.removeprefix("# via").split()  # `# via a`, or `# via` then `#   a` lines
            elif comment.startswith("#") and len(lines) > 1 and lines[-2].strip().startswith("#"):
                needed_by += comment.removeprefix("#").split()
    ros = {name for name, _, _ in entries if name.startswith(ROS_WHEEL_PREFIX)}
    grew = True
    while grew:
        grew = False
        for name, _, needed_by in entries:
            if name not in ros and needed_by and all(parent in ros for parent in needed_by):
                ros.add(name)
                grew = True
    head = text[: len(text) - len("".join(line for _, lines, _ in entries for line in lines))]
    return head + "".join("".join(lines) for name, lines, _ in entries if name not in ros)


@cache
def _exported(extras_needed: tuple[str, ...]) -> str:
    extra_options = [word for extra in extras_needed for word in ("--extra", extra)]
    return uv(
        "export",
        "--frozen",
        "--no-dev",
        "--no-emit-workspace",
        "--no-header",
        "--format",
        "requirements.txt",
        "--package",
        RUNTIME_PACKAGE,
        *extra_options,
    )


def local_requirements(built: dict[str, bytes]) -> str:
    """The built wheels as requirements pinned with their SHA-256, paths relative to the wheel directory."""
    lines = [
        f"# The wheels built with this bundle; install.sh installs them from {WHEEL_DIR}/ with --require-hashes.\n"
    ]
    for name, data in sorted(built.items()):
        lines.append(f"./{name} --hash=sha256:{hashlib.sha256(data).hexdigest()}\n")
    return "".join(lines)


def bundle_files(robot: Robot) -> dict[str, str | bytes]:
    """The bundle's files by path relative to the output directory (one bundle per host when it has hosts)."""
    _check_source_tree()
    built = wheels()
    if not robot.hosts:
        return _bundle(robot, built)
    files: dict[str, str | bytes] = {}
    for host in robot.hosts:
        part = _bundle(robot.for_host(host.name), built)
        files.update({host_path(host.name, path): data for path, data in part.items()})
    return files


def _check_source_tree() -> None:
    if not (SOURCE_ROOT / "uv.lock").is_file() or not all(
        (SOURCE_ROOT / member / "pyproject.toml").is_file() for member in PACKAGES.values()
    ):
        raise BundleError(
            f"--bundle builds the runtime from joshuac's source tree, which {SOURCE_ROOT} is not; "
            "run the joshuac of a checkout of the repository"
        )


def _bundle(robot: Robot, built: dict[str, bytes]) -> dict[str, str | bytes]:
    host = robot.this_host
    ros_system = host is not None and host.ros_from_system
    script = template(
        "install.sh.j2",
        robot=robot,
        venv=DEFAULT_VENV,
        python=(host.python if host is not None and host.python else PYTHON),
        ros_setup=ROS_SYSTEM_SETUP if ros_system else "",
        ros_wheels_python=ROS_WHEELS_PYTHON,
        ros_wheels_platform=f"{ROS_WHEELS_PYTHON} on {ROS_WHEELS_MACHINE}",
        wheels=sorted(built),
        wheel_dir=WHEEL_DIR,
        stamp=STAMP,
        requirements=REQUIREMENTS,
        local_requirements=LOCAL_REQUIREMENTS,
        local_requirements_name=LOCAL_REQUIREMENTS_NAME,
        extras=extras(robot),
        format_version=FORMAT_VERSION,
        release_key=DEFAULT_RELEASE_KEY,
    )
    files: dict[str, str | bytes] = {f"{WHEEL_DIR}/{name}": data for name, data in built.items()}
    files[REQUIREMENTS] = requirements(robot, without_ros=ros_system)
    files[LOCAL_REQUIREMENTS] = local_requirements(built)
    files[INSTALL_SCRIPT] = script
    return files
