"""Render the model into `{relative path: text}` through the Jinja2 templates (pure; no disk writes)."""

from dataclasses import dataclass
from functools import cache
from pathlib import Path

import jinja2

from joshua_codegen import escape
from joshua_codegen.model import Robot
from joshua_codegen.version import VERSION

TEMPLATE_DIRS = (Path(__file__).parent / "_templates", Path(__file__).resolve().parent.parent / "templates")
DEFAULT_PREFIX = "/opt/joshua/{robot}"


@dataclass(frozen=True)
class Context:
    """What every emitter receives besides the model."""

    prefix: str  # where the output directory lives on the robot
    version: str = VERSION


@cache
def environment() -> jinja2.Environment:
    """The one template environment: undefined variables fail the build."""
    directory = next(d for d in TEMPLATE_DIRS if d.is_dir())
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(directory)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )
    env.filters.update(
        py=escape.python_literal,
        one_line=escape.one_line,
        xml_comment=escape.xml_comment,
        dot_id=escape.dot_id,
        mermaid=escape.mermaid_label,
    )
    return env


def template(name: str, **values) -> str:
    return environment().get_template(name).render(version=VERSION, **values)


def effective_prefix(robot_name: str, prefix: str | None) -> str:
    """Where the output directory lives on the robot: `prefix`, or the default for the robot."""
    return (prefix or DEFAULT_PREFIX.format(robot=robot_name)).rstrip("/") or "/"


def render(robot: Robot, prefix: str | None = None) -> dict[str, str]:
    """Every output file of a robot, by path relative to the output directory."""
    from joshua_codegen.emitters import EMITTERS

    context = Context(prefix=effective_prefix(robot.name, prefix))
    files: dict[str, str] = {}
    for emit in EMITTERS:
        files.update(emit(robot, context))
    return dict(sorted(files.items()))


def is_executable(path: str) -> bool:
    """Generated scripts get mode 0755, everything else 0644."""
    return path.endswith(".py")
