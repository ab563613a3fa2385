"""Containerfile and .containerignore of `build --image`: a multi-stage image that runs the robot's supervisor.

Stages: `robot` is the base with the run-time system packages and the user, the bundle (OUT/wheels,
OUT/install.sh) installed into a virtual environment where it runs (no stage copies it); `cpp` (only
for a robot with C++ binaries) compiles them on top of it, against that environment, so the rpaths they
carry hold the image's paths; the image is `robot` with the binaries: no compiler, no pip cache, no secret.
"""

import math
import posixpath
import re
from dataclasses import dataclass

from joshua_codegen.bundle import DEFAULT_VENV, REQUIREMENTS, extras
from joshua_codegen.emitters import process_launch, supervisor
from joshua_codegen.model import Robot
from joshua_codegen.render import template

CONTAINERFILE = "Containerfile"
CONTAINERIGNORE = ".containerignore"
DEFAULT_BASE = "debian:bookworm-slim"  # Debian 12: Python 3.11, what the locked requirements are resolved for
VENV = DEFAULT_VENV  # install.sh's default
PAGE_DIR = "web"  # the dashboard's page, in the build context and under the prefix in the image
CPP_DIR = "cpp"  # the C++ nodes' sources, in the build context
CPP_BUILD_DIR = "/tmp/joshua/build"
CPP_JOBS = 2
# The cache mount pip keeps the requirements' wheels in (`RUN --mount=type=cache,id=...`), shared by the builds.
WHEEL_CACHE_ID = "joshua-wheels"
WHEEL_CACHE = "/var/cache/joshua-wheels"
CA_SECRET = "ca-certificates"  # `--secret id=ca-certificates,src=FILE`: the CA bundle pip trusts while building
USER = "joshua"
USER_ID = 1000
USER_GROUPS = ("dialout", "video")  # serial adapters and cameras belong to these groups on Debian hosts
INIT = "/usr/bin/catatonit"
STOP_SIGNAL = "SIGINT"  # the supervisor's own cascade begins with SIGINT
STOP_MARGIN_S = 3.0  # beyond the cascade's graces: the supervisor reaps, cleans up and exits
STOP_TIMEOUT_LABEL = "io.joshua.stop-timeout"
ROBOT_LABEL = "io.joshua.robot"
# Debian packages each stage needs; the ones the base already has are not installed again.
BUILD_PACKAGES = ("python3", "python3-venv")  # what makes the environment, in the robot's stage
CPP_PACKAGES = ("g++", "make", "nlohmann-json3-dev", "libpython3.11-dev")
RUN_PACKAGES = ("python3", "catatonit")
CPP_RUN_PACKAGES = ("libpython3.11",)  # the ROS message libraries the binaries load need libpython's symbols
# What a runtime extra needs from the system: MuJoCo renders offscreen through Mesa's EGL.
EXTRA_PACKAGES = {"sim": ("libegl1", "libegl-mesa0", "libgl1-mesa-dri", "libgles2", "libgl1")}
DEVICE_OPTIONS = {"serial": "--device", "camera": "--device"}  # other kinds (files, models) are mounted read-only
# What a Containerfile can hold without quoting: COPY, ENV and make take these paths as they are.
PLAIN_PATH = re.compile(r"/[A-Za-z0-9._+@/-]*")


class ContainerfileError(Exception):
    """The robot cannot be written as a Containerfile (a path it cannot hold)."""


@dataclass(frozen=True)
class RunOption:
    """One option of `podman run` / `docker run` this robot needs, and why."""

    option: str
    reason: str


def stop_timeout_s(robot: Robot) -> int:
    """Whole seconds a container needs to stop: the cascade's graces and a margin."""
    return math.ceil(robot.sigint_grace_s + robot.sigterm_grace_s + STOP_MARGIN_S)


def robot_packages(robot: Robot, binaries: list[str]) -> list[str]:
    """Debian packages of the robot's stage (the image): Python, the init, what the robot's extras and binaries
    need, and what makes the environment there; each once, in that order."""
    packages = list(RUN_PACKAGES)
    for extra in extras(robot):
        packages += EXTRA_PACKAGES.get(extra, ())
    if binaries:
        packages += CPP_RUN_PACKAGES
    return list(dict.fromkeys([*packages, *BUILD_PACKAGES]))


def run_options(robot: Robot) -> list[RunOption]:
    """What `run` needs to be given: the devices, files and models the nodes claim, the output directories."""
    options, seen = [], set()
    for process in robot.processes:
        for device in process.devices:
            flag = DEVICE_OPTIONS.get(device.kind)
            option = f"{flag} {device.path}" if flag else f"-v {device.path}:{device.path}:ro"
            if option not in seen:
                seen.add(option)
                options.append(RunOption(option, f"{device.kind} of node {process.name}"))
        output = robot.process_settings(process).output_directory if process.kind == "python" else ""
        if output and output not in seen:
            seen.add(output)
            options.append(
                RunOption(f"-v DIR:{output}", f"where node {process.name} writes (writable by uid {USER_ID})")
            )
    return options


def _plain(path: str, what: str) -> str:
    if not PLAIN_PATH.fullmatch(path) or "//" in path:
        raise ContainerfileError(
            f"{what} {path!r} cannot be written in a Containerfile: use letters, digits and . _ + @ - / only"
        )
    return path


def containerfile(robot: Robot, prefix: str, binaries: list[str], page: bool) -> str:
    """The Containerfile of a robot built with `prefix`, compiling `binaries`, serving the page when `page`."""
    prefix = _plain(prefix, "--prefix")
    cpp_bin_dir = _plain(process_launch.under(prefix, robot.cpp_bin_dir), "cpp_bin_dir") if binaries else ""
    return template(
        "Containerfile.j2",
        robot=robot,
        prefix=prefix,
        venv=VENV,
        default_base=DEFAULT_BASE,
        cpp_packages=CPP_PACKAGES,
        robot_packages=robot_packages(robot, binaries),
        requirements=REQUIREMENTS,
        wheel_cache_id=WHEEL_CACHE_ID,
        wheel_cache=WHEEL_CACHE,
        binaries=binaries,
        cpp_dir=posixpath.join(prefix, CPP_DIR),
        cpp_build_dir=CPP_BUILD_DIR,
        cpp_jobs=CPP_JOBS,
        cpp_bin_dir=cpp_bin_dir,
        web_dir=posixpath.join(prefix, PAGE_DIR) if page else "",
        secret=CA_SECRET,
        user=USER,
        user_id=USER_ID,
        user_groups=",".join(USER_GROUPS),
        init=INIT,
        supervisor_flags=supervisor.INTERPRETER_FLAGS,
        stop_signal=STOP_SIGNAL,
        stop_timeout=stop_timeout_s(robot),
        sigint_grace=f"{robot.sigint_grace_s:g}",
        sigterm_grace=f"{robot.sigterm_grace_s:g}",
        stop_margin=f"{STOP_MARGIN_S:g}",
        stop_timeout_label=STOP_TIMEOUT_LABEL,
        robot_label=ROBOT_LABEL,
        options=run_options(robot),
    )


def containerignore(robot: Robot, paths: list[str]) -> str:
    """Everything out of the build context except `paths`: the files of the build, which install.sh checks."""
    return template("containerignore.j2", robot=robot, paths=sorted(paths))
