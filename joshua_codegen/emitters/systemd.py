"""systemd/: one target per robot and one service per process, with supervisor.py's cascade and restarts."""

import posixpath
from types import SimpleNamespace

from joshua_codegen import escape
from joshua_codegen.emitters import fastdds, process_launch
from joshua_codegen.model import Process, Robot
from joshua_codegen.render import Context, template
from joshua_core import exit_codes

SYSTEMD_RESTART = {"RESTART_NEVER": "no", "RESTART_ON_FAILURE": "on-failure", "RESTART_ALWAYS": "always"}
MIN_TIMESPAN_MS = 1  # systemd reads 0 as "no timeout at all"
# Readiness of nodes that speak sd_notify (joshua_runtime.notify): how long systemd waits for READY=1,
# and the watchdog their loop feeds every WATCHDOG_S / 2.
READY_TIMEOUT_S = 90.0
WATCHDOG_S = 20.0


def target_name(robot: Robot) -> str:
    return f"joshua-{robot.name}.target"


def service_name(robot: Robot, process: Process) -> str:
    return f"joshua-{robot.name}-{process.name}.service"


def timespan(seconds: float) -> str:
    """A systemd time span: whole seconds as `5s`, else milliseconds (`300ms`)."""
    milliseconds = max(MIN_TIMESPAN_MS, round(seconds * 1000))
    return f"{milliseconds // 1000}s" if milliseconds % 1000 == 0 else f"{milliseconds}ms"


def restart(process: Process) -> str:
    return "no" if process.max_restarts == 0 else SYSTEMD_RESTART[process.restart]


def notifies(process: Process) -> bool:
    """The node sends READY=1 and WATCHDOG=1: a runtime node, Python or the C++ binary chosen at start.

    CUSTOM programs may not speak the protocol."""
    return process.kind == "python"


def command(robot: Robot, process: Process, prefix: str) -> tuple[list[str], list[tuple[str, str]]]:
    """(the words ExecStart= runs, the variables Environment= sets) of one service."""
    words = process_launch.launch_words(robot, process, prefix, [process_launch.ENV_COMMAND], prefix)
    variables = process_launch.node_environment(robot, process, posixpath.join(prefix, fastdds.profile_path(process)))
    environment = [(key, value) for key, value in variables if process_launch.ENVIRONMENT_NAME.fullmatch(key)]
    words = process_launch.through_env(  # keys Environment= would refuse reach the node through env(1)
        words, [f"{key}={value}" for key, value in variables if not process_launch.ENVIRONMENT_NAME.fullmatch(key)]
    )
    return words, environment


def command_lines(robot: Robot, process: Process, prefix: str) -> tuple[str, list[str]]:
    """(the ExecStart= value, the Environment= values) of one service, quoted."""
    return quoted(*command(robot, process, prefix))


def quoted(words: list[str], environment: list[tuple[str, str]]) -> tuple[str, list[str]]:
    """(the ExecStart= value, the Environment= values) of the words and variables `command` gives, quoted."""
    return (
        escape.systemd_command(words),
        [escape.systemd_quote(f"{key}={value}", exec_line=False) for key, value in environment],
    )


def service(robot: Robot, process: Process, prefix: str, first: list[Process]) -> SimpleNamespace:
    """The values of one service unit; `first` are the processes every other one starts after. Attributes, not
    dict keys: the template reads each as `unit.name`, which Jinja2 tries as an attribute first."""
    exec_start, environment = command_lines(robot, process, prefix)
    delays = process_launch.backoff_delays(process.max_restarts)
    return SimpleNamespace(
        **{
            "name": service_name(robot, process),
            "description": escape.systemd_raw(f"joshua robot {robot.name}: node {process.name} ({process.node_type})"),
            "syslog_identifier": escape.systemd_raw(process.name),
            "exec_start": exec_start,
            "environment": environment,
            "restart": restart(process),
            "restart_sec": timespan(process_launch.RESTART_DELAY_INITIAL_S),
            "restart_steps": max(1, sum(1 for before, after in zip(delays, delays[1:]) if after > before)),
            "restart_max_delay": timespan(delays[-1] if delays else process_launch.RESTART_DELAY_INITIAL_S),
            "start_limit_burst": process.max_restarts + 1,
            "start_limit_interval": timespan((process.max_restarts + 1) * process_launch.RESTART_RESET_AFTER_S),
            "working_directory": escape.systemd_raw(prefix),
            "uses_cpp": bool(process.cpp_binary),
            "settings_exit_code": exit_codes.NODE_EXIT_SETTINGS if process.kind != "custom" else None,
            "notify": notifies(process),
            "ready_timeout": timespan(READY_TIMEOUT_S),
            "watchdog": timespan(WATCHDOG_S),
            "cpp_binary": process_launch.cpp_binary_path(robot, process, prefix) if process.cpp_binary else "",
            "after": [service_name(robot, starter) for starter in first if starter is not process],
        }
    )


def emit(robot: Robot, context: Context) -> dict[str, str]:
    shutdown = SimpleNamespace(sigint=timespan(robot.sigint_grace_s), sigterm=timespan(robot.sigterm_grace_s))
    files = {}
    first = [process for process in robot.processes if process.starts_first]  # once: a robot has thousands
    for process in robot.processes:
        unit = service(robot, process, context.prefix, first)
        files[f"systemd/{unit.name}"] = template(
            "node.service.j2",
            robot=robot,
            process=process,
            unit=unit,
            shutdown=shutdown,
            target=target_name(robot),
            policy=process_launch,
        )
    critical = [service_name(robot, p) for p in robot.processes if p.critical]
    optional = [service_name(robot, p) for p in robot.processes if not p.critical]
    files[f"systemd/{target_name(robot)}"] = template(
        "robot.target.j2",
        robot=robot,
        critical=critical,
        optional=optional,
        shutdown=shutdown,
        description=escape.systemd_raw(f"joshua robot {robot.name}"),
    )
    return files
