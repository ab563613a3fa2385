"""Render the model into `{relative path: text}` through the Jinja2 templates (pure; no disk writes).

Jinja2 compiles a template from source in about 3 ms; with 13 templates that was most of a build's
own work. The compiled code is kept beside the templates (`_template_cache/`, made by `make setup`
and refreshed by any build that may write there); Jinja2 checks each entry against its template's
source and compiles again when they differ, so a stale entry is never used.
"""

from dataclasses import dataclass
from functools import cache
from pathlib import Path

from joshua_codegen import escape
from joshua_codegen.model import Robot
from joshua_codegen.version import VERSION

TEMPLATE_DIRS = (Path(__file__).parent / "_templates", Path(__file__).resolve().parent.parent / "templates")
TEMPLATE_CACHE_DIR = Path(__file__).parent / "_template_cache"
DEFAULT_PREFIX = "/opt/joshua/{robot}"


@dataclass(frozen=True)
class Context:
    """What every emitter receives besides the model."""

    prefix: str  # where the output directory lives on the robot
    version: str = VERSION


@cache
def environment():
    """The one template environment: undefined variables fail the build. Jinja2 is imported here, so
    a command that renders nothing never loads it."""
    import jinja2

    from joshua_codegen.template_cache import PackageBytecodeCache

    directory = next(d for d in TEMPLATE_DIRS if d.is_dir())
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(directory)),
        bytecode_cache=PackageBytecodeCache(TEMPLATE_CACHE_DIR),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
        auto_reload=False,  # templates ship with the package: no stat(2) of the template per file rendered
    )
    env.filters.update(
        py=escape.python_literal,
        sh=escape.shell_word,
        one_line=escape.one_line,
        xml_comment=escape.xml_comment,
        xml_duration=xml_duration,
        dot_id=escape.dot_id,
        mermaid=escape.mermaid_label,
        ansible=escape.ansible_value,
    )
    return env


def xml_duration(milliseconds: int) -> str:
    """A Fast DDS XML duration: `<sec>S</sec><nanosec>N</nanosec>`."""
    return f"<sec>{milliseconds // 1000}</sec><nanosec>{milliseconds % 1000 * 1_000_000}</nanosec>"


def template(name: str, **values) -> str:
    return environment().get_template(name).render(version=VERSION, **values)


def effective_prefix(robot_name: str, prefix: str | None) -> str:
    """Where the output directory lives on the robot: `prefix`, or the default for the robot."""
    return (prefix or DEFAULT_PREFIX.format(robot=robot_name)).rstrip("/") or "/"


def render(robot: Robot, prefix: str | None = None) -> dict[str, str]:
    """Every output file of a robot, by path relative to the output directory.

    A robot on several hosts gets the whole graph (manifest.json, topology.*) at the top and one complete
    output per host in `hosts/<name>/`, each for the same prefix on its own computer."""
    from joshua_codegen.emitters import EMITTERS, WHOLE_ROBOT

    context = Context(prefix=effective_prefix(robot.name, prefix))
    files: dict[str, str] = {}
    if not robot.hosts:
        for emit in EMITTERS:
            files.update(emit(robot, context))
        return dict(sorted(files.items()))
    whole: dict[str, str] = {}
    for emit in WHOLE_ROBOT:
        whole.update(emit(robot, context))
    files.update(whole)
    for host in robot.hosts:
        part = robot.for_host(host.name)
        host_files = dict(whole)  # the graph of the whole robot; manifest.json is the host's own below
        for emit in EMITTERS:
            if emit not in WHOLE_ROBOT or emit is WHOLE_ROBOT[0]:
                host_files.update(emit(part, context))
        files.update({host_path(host.name, path): text for path, text in host_files.items()})
    return dict(sorted(files.items()))


HOSTS_DIR = "hosts"


def host_path(host: str, path: str = "") -> str:
    """Where a file of one host's output is, relative to the output directory."""
    return f"{HOSTS_DIR}/{host}/{path}" if path else f"{HOSTS_DIR}/{host}"


SUPERVISOR_CODE_PATH = "supervisor_code.py"  # the code supervisor.py runs (emitters/supervisor.py)
# Python files that are modules another generated script runs, not scripts themselves.
NOT_SCRIPTS = (SUPERVISOR_CODE_PATH,)


def is_executable(path: str) -> bool:
    """Generated scripts get mode 0755, everything else 0644."""
    return path.endswith((".py", ".sh")) and path.rsplit("/", 1)[-1] not in NOT_SCRIPTS
