"""E118 command-too-long: a node's command line or environment is longer than exec(2) or systemd accept.

What it checks:
    For every process, from the very command lines joshuac generates (with `--prefix`, else the
    default): each argument and each environment entry (`NAME=value`) is at most 131071 bytes
    (Linux's MAX_ARG_STRLEN, 131072 with the terminating NUL); all of them together at most 1 MiB
    (half of the 2 MiB exec allows with the default 8 MiB stack, the rest left to the environment
    the node inherits); each line of the systemd unit (ExecStart=, Environment=) is shorter than
    1 MiB (systemd's LONG_LINE_MAX; it refuses a unit with a longer line). A C++ node's
    `-p name:=value` parameters all go into one `sh -c` argument under systemd and supervisord.

Why it matters:
    exec fails with E2BIG ("Argument list too long") and systemd refuses to load the unit: the
    node would fail at every start, after the build had succeeded.

Example:
    node {
      type: CUSTOM
      executable: "/usr/bin/tool"
      args: ["aaaa…(200000 letters)"]   # error: an argument of 200000 bytes; exec accepts at most 131071
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.emitters import systemd
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding, strings_of

CODE = "E118"
NAME = "command-too-long"
SEVERITY = ERROR
STAGE = "plan"
MAX_ARG_STRLEN = 131072  # bytes of one argument or environment entry, its terminating NUL included
MAX_COMMAND_BYTES = 1024 * 1024  # budget of a node's own arguments and environment together
LONG_LINE_MAX = 1024 * 1024  # systemd refuses unit file lines of this many bytes or more


def _size(text: str) -> int:
    return len(text.encode("utf-8"))


def _problem(robot, process, prefix: str) -> str | None:
    words, environment = systemd.command(robot, process, prefix)
    entries = [f"{key}={value}" for key, value in environment]
    longest = max(words + entries, key=_size)
    if _size(longest) >= MAX_ARG_STRLEN:
        return (
            f"its command line would hold an argument of {_size(longest)} bytes; exec accepts at most "
            f"{MAX_ARG_STRLEN - 1} in one argument or environment entry (E2BIG)"
        )
    total = sum(_size(text) + 1 for text in words + entries)
    if total > MAX_COMMAND_BYTES:
        return (
            f"its command line and environment would total {total} bytes; the limit is {MAX_COMMAND_BYTES} "
            "(1 MiB) so that exec cannot fail with E2BIG"
        )
    exec_start, assignments = systemd.quoted(words, environment)
    lines = [f"ExecStart={exec_start}"] + [f"Environment={assignment}" for assignment in assignments]
    line = max(lines, key=_size)
    if _size(line) >= LONG_LINE_MAX:
        return (
            f"its systemd unit would have a line of {_size(line)} bytes ({line.split('=', 1)[0]}=); systemd "
            f"refuses lines of {LONG_LINE_MAX} bytes (1 MiB) or more"
        )
    return None


def _largest_value(ctx, process) -> tuple:
    """The written field of the process's node (or robot) holding the longest string: where to point."""
    view = next((view for view in ctx.nodes if view.name == process.name), None)
    message, path = (view.node, view.path) if view is not None else (ctx.config, ROBOT)
    strings = [(len(text), at) for at, _, text in strings_of(message, path)]
    return max(strings, key=lambda item: item[0])[1] if strings else path


def check(ctx):
    robot = ctx.robot
    for process in robot.processes:
        problem = _problem(robot, process, ctx.prefix)
        if problem is not None:
            yield Finding(_largest_value(ctx, process), f'process "{process.name}": {problem}')
