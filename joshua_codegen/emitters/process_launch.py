"""How nodes are launched and restarted: the backoff the three process managers share, and the
command lines systemd and supervisord run (supervisor.py decides the same things at run time)."""

import posixpath
import re
import shlex
from functools import cache

from joshua_codegen.escape import shell_word
from joshua_codegen.model import Process, Robot
from joshua_codegen.placement import ROS_SYSTEM_SETUP
from joshua_codegen.supervisor.policy import (  # the backoff the three process managers share
    CPP_FALLBACK_WARNING,
    RESTART_DELAY_CAP_S,
    RESTART_DELAY_FACTOR,
    RESTART_DELAY_INITIAL_S,
)
from joshua_codegen.supervisor.policy import (
    RESTART_RESET_AFTER_S as RESTART_RESET_AFTER_S,  # re-exported for the systemd emitter
)

FASTDDS_PROFILE_VARIABLE = "FASTRTPS_DEFAULT_PROFILES_FILE"
ENVIRONMENT_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")  # what Environment= and environment= accept as a key
ENV_COMMAND = "/usr/bin/env"
SHELL = "/bin/sh"


def robot_environment(robot: Robot) -> dict[str, str]:
    """The variables every node of the robot gets besides the DDS profile."""
    variables = {"PYTHONUNBUFFERED": "1"}
    if robot.ros_domain_id is not None:
        variables["ROS_DOMAIN_ID"] = str(robot.ros_domain_id)
    return variables


def node_environment(robot: Robot, process: Process, profile_path: str) -> list[tuple[str, str]]:
    """The variables every node gets, then the description's own (which win)."""
    variables = {FASTDDS_PROFILE_VARIABLE: profile_path, **robot_environment(robot)}
    variables.update(process.env)
    return list(variables.items())


def through_env(words: list[str], assignments: list[str]) -> list[str]:
    """`words` run by env(1) with `assignments` (KEY=VALUE) that a unit format cannot express itself."""
    return [ENV_COMMAND, *assignments, *words] if assignments else words


def under(base: str, path: str) -> str:
    """`path` when absolute, else `base/path`."""
    return path if path.startswith("/") else posixpath.join(base, path)


def program(name: str, base: str, bare: list[str]) -> list[str]:
    """The words that run program `name`: a bare name through `bare` (PATH lookup), a relative path
    under `base`, an absolute path as it is."""
    if "/" not in name:
        return [*bare, name]
    return [under(base, name)]


def cpp_binary_path(robot: Robot, process: Process, base: str) -> str:
    return under(under(base, robot.cpp_bin_dir), process.cpp_binary)


def fallback_warning(process: Process, binary: str) -> str:
    return f"{process.name}: {CPP_FALLBACK_WARNING.format(binary=binary)}"


def launch_words(robot: Robot, process: Process, base: str, bare: list[str], workdir: str) -> list[str]:
    """The argv that starts one node, resolving paths against `base` (the output directory on the robot);
    on a host with ROS 2 from apt, run after sourcing its setup script (with_system_ros)."""
    words = _node_words(robot, process, base, bare, workdir)
    host = robot.this_host
    return with_system_ros(words) if host is not None and host.ros_from_system else words


def with_system_ros(words: list[str]) -> list[str]:
    """`words` run by sh after it sourced the ROS setup script; `exec` keeps the node the main process."""
    return [SHELL, "-c", f'. {shlex.quote(ROS_SYSTEM_SETUP)} && exec "$0" "$@"', *words]


def _node_words(robot: Robot, process: Process, base: str, bare: list[str], workdir: str) -> list[str]:
    """A node with a C++ binary is started through `/bin/sh -c` so that the binary is chosen when it
    exists and is executable at launch time, like supervisor.py does; otherwise the Python entrypoint
    runs after one warning line. `exec` keeps the node itself as the main process.
    """
    if process.kind == "custom":
        return [*program(process.executable, workdir, bare), *process.args]
    python = [*program(robot.python_executable, base, bare), under(base, process.entrypoint)]
    if not process.cpp_binary:
        return python
    binary = cpp_binary_path(robot, process, base)
    quoted = shlex.quote(binary)
    script = (
        f"if [ -f {quoted} ] && [ -x {quoted} ]; then exec {' '.join(map(shell_word, [binary, *process.cpp_args]))}; fi; "
        f"echo {shlex.quote(fallback_warning(process, binary))} >&2; exec {shlex.join(python)}"
    )
    return [SHELL, "-c", script]


@cache
def backoff_delays(count: int) -> tuple[float, ...]:
    """The waits before restarts 1..count of a node that keeps failing (the same few counts for every node)."""
    delays, delay = [], RESTART_DELAY_INITIAL_S
    for _ in range(count):
        delays.append(delay)
        delay = min(delay * RESTART_DELAY_FACTOR, RESTART_DELAY_CAP_S)
    return tuple(delays)
