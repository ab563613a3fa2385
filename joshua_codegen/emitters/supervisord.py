"""supervisord.conf: every process as a [program:] of one group, with the closest cascade and restarts."""

import math
from types import SimpleNamespace

from joshua_codegen import escape
from joshua_codegen.emitters import fastdds, process_launch, supervisor
from joshua_codegen.model import Process, Robot
from joshua_codegen.render import Context, template

CONF_PATH = "supervisord.conf"
HERE = "\x01here\x01"  # stands for supervisord's %(here)s (the directory of the conf) until escaping is done
STARTSECS = 1  # a node must run this long to count as started; earlier exits use up startretries
FIRST_PRIORITY = 1  # started before the others (supervisord's default priority is 999)


def group_name(robot: Robot) -> str:
    return f"joshua-{robot.name}"


def _here(text: str) -> str:
    return text.replace(HERE, "%(here)s")


def program(robot: Robot, process: Process) -> SimpleNamespace:
    """The settings of one [program:] section (attributes: the template reads `program.name`)."""
    words = process_launch.launch_words(robot, process, HERE, [], HERE)
    variables = process_launch.node_environment(robot, process, f"{HERE}/{fastdds.profile_path(process)}")
    environment, others = [], []
    for key, value in variables:  # what environment= cannot hold reaches the node through env(1)
        try:
            if not process_launch.ENVIRONMENT_NAME.fullmatch(key):
                raise ValueError(key)
            environment.append(f"{key}={escape.supervisor_value(value)}")
        except ValueError:
            others.append(f"{key}={value}")
    words = process_launch.through_env(words, others)
    never = process.restart == "RESTART_NEVER" or process.max_restarts == 0
    return SimpleNamespace(
        **{
            "name": process.name,
            "command": _here(escape.supervisor_command(words)),
            "environment": _here(",".join(environment)),
            "autorestart": "false"
            if never
            else {"RESTART_ON_FAILURE": "unexpected", "RESTART_ALWAYS": "true"}[process.restart],
            "startsecs": 0 if never else STARTSECS,
            "startretries": 0 if never else process.max_restarts,
            "priority": FIRST_PRIORITY if process.starts_first else None,
        }
    )


def listener_command(robot: Robot) -> str:
    """supervisor.py in its supervisord event listener mode (stops supervisord when a critical node fails)."""
    words = [
        *process_launch.program(robot.python_executable, HERE, []),
        *supervisor.INTERPRETER_FLAGS,
        f"{HERE}/{supervisor.SUPERVISOR_PATH}",
        "--supervisord-listener",
    ]
    return _here(escape.supervisor_command(words))


def emit(robot: Robot, context: Context) -> dict[str, str]:
    stop_wait = math.ceil(robot.sigint_grace_s + robot.sigterm_grace_s)
    programs = [program(robot, process) for process in robot.processes]
    listener = listener_command(robot) if any(process.critical for process in robot.processes) else ""
    text = template(
        "supervisord.conf.j2",
        robot=robot,
        group=group_name(robot),
        programs=programs,
        stop_wait=max(1, stop_wait),
        startsecs=STARTSECS,
        listener=listener,
        initial_delay=process_launch.RESTART_DELAY_INITIAL_S,
    )
    return {CONF_PATH: text}
