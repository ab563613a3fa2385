"""`joshuac check FLEET`: the fleet file's own rules, and every robot's description checked with its overrides.

Each robot is checked as `joshuac check DESCRIPTION --set name=ROBOT [--set ...] --set SET...` would check
it, for the prefix its release has on the robot (/opt/joshua/current). Problems of an override point
at its `set` line in the fleet file; problems of a description point into the description, once
however many robots share it, each robot that met it named in a note. A robot whose description
leaves `python_executable` unset runs the release's own environment (RELEASE_PYTHON).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

from joshua_codegen.check import CheckResult, check_text, decode
from joshua_codegen.diagnostics import Diagnostic, Related, sort_diagnostics
from joshua_codegen.fleet.load import load_fleet, robot_path
from joshua_codegen.load import load_text
from joshua_codegen.overrides import OVERRIDE_PATH
from joshua_codegen.positions import Location, SourceMap
from joshua_codegen.rules import run_rules
from joshua_codegen.source_file import SourceProblem, read_description
from joshua_core.names import is_robot_name
from joshua_core.schema import FleetConfig, FleetRobot, RobotConfig

ROBOT_ROOT = "/opt/joshua"  # where releases live on every robot (release_tool.py's default root)
FLEET_PREFIX = f"{ROBOT_ROOT}/current"  # the --prefix of every robot's build: the release `current` points at
RELEASE_PYTHON = f"{FLEET_PREFIX}/venv/bin/python3"  # the environment install.sh makes in each release


@dataclass
class FleetMember:
    """One robot of the fleet as checked: its entry, its description's path, and the check with its overrides."""

    index: int
    entry: FleetRobot
    description_path: str = ""  # relative to the working directory, as diagnostics name it
    check: CheckResult | None = None  # None when the description could not be read

    @property
    def config(self) -> RobotConfig | None:
        """The robot's configuration with its overrides, when it was read whole."""
        return self.check.description.robot_config if self.check and self.check.description else None


@dataclass
class FleetCheckResult(CheckResult):
    fleet: FleetConfig | None = None
    members: list[FleetMember] = field(default_factory=list)

    @property
    def sources(self) -> dict[str, str]:
        """The fleet file, every description it names, and the command line's overrides."""
        sources = {self.path: self.text}
        for member in self.members:
            if member.check is not None:
                sources[member.check.path] = member.check.text
        if self.overrides:
            sources[OVERRIDE_PATH] = "\n".join(self.overrides)
        return sources


@dataclass
class FleetContext:
    """What the fleet rules (STAGE "fleet") read."""

    fleet: FleetConfig
    source: SourceMap
    members: list[FleetMember]
    unknown_nodes: frozenset = frozenset()


def description_path(fleet_path: str, description: str) -> str:
    return os.path.normpath(os.path.join(os.path.dirname(fleet_path), description))


def _sets_python(path: str, text: str) -> bool:
    loaded = load_text(path, text)
    description = loaded.description or loaded.partial
    return description is not None and bool(description.robot_config.python_executable)


class _OverrideLines:
    """Where each override line of one robot's check comes from: the fleet file, or the command line."""

    def __init__(self, source: SourceMap, index: int, implicit: list[tuple], command_line: int):
        self.source, self.index, self.implicit, self.command_line = source, index, implicit, command_line

    def location(self, line: int) -> Location:
        implicit = len(self.implicit)
        if line <= implicit:
            return self.source.locate(self.implicit[line - 1])
        if line <= implicit + self.command_line:
            return Location(OVERRIDE_PATH, line - implicit, 1)
        return self.source.locate(robot_path(self.index, "set", line - implicit - self.command_line - 1))

    def diagnostic(self, diagnostic: Diagnostic) -> Diagnostic:
        related = tuple(self.related(note) for note in diagnostic.related)
        if diagnostic.path != OVERRIDE_PATH:
            return replace(diagnostic, related=related)
        where = self.location(diagnostic.line)
        if where.path == OVERRIDE_PATH:
            return replace(diagnostic, line=where.line, end_line=where.line, related=related)
        return replace(
            diagnostic,
            path=where.path,
            line=where.line,
            column=where.column,
            end_line=where.end_line,
            end_column=where.end_column,
            related=related,
        )

    def related(self, note: Related) -> Related:
        if note.path != OVERRIDE_PATH:
            return note
        where = self.location(note.line)
        return Related(where.path, where.line, where.column, note.message)


def implicit_overrides(index: int, entry: FleetRobot, sets_python: bool) -> list[tuple[str, tuple]]:
    """(override, where in the fleet file it comes from) that make a description this robot: its name, its
    computers' addresses, and the release's environment unless the description names an interpreter."""
    implicit = [(f"name={entry.name}", robot_path(index, "name"))] if is_robot_name(entry.name) else []
    for number, host in enumerate(entry.host):
        if host.name and host.address:
            implicit.append((f"host.{host.name}.address={host.address}", robot_path(index, "host", number)))
    if not sets_python:
        implicit.append((f"python_executable={RELEASE_PYTHON}", robot_path(index, "name")))
    return implicit


def check_member(fleet_path: str, source: SourceMap, index: int, entry: FleetRobot, command_line: Sequence[str]):
    """(the member, its diagnostics with override lines placed in the fleet file)."""
    member = FleetMember(index, entry)
    if not entry.description:
        return member, []  # E601 reports it
    member.description_path = description_path(fleet_path, entry.description)
    try:
        data = read_description(member.description_path)
    except SourceProblem as problem:
        where = source.locate(robot_path(index, "description"))
        found = problem.diagnostic
        message = f"{entry.description}: {found.message}"
        return member, [Diagnostic(where.path, where.line, where.column, found.code, found.severity, message)]
    text, problems = decode(member.description_path, data)
    if text is None:
        return member, problems
    implicit = implicit_overrides(index, entry, _sets_python(member.description_path, text))
    overrides = [*(override for override, _ in implicit), *command_line, *entry.set]
    member.check = check_text(member.description_path, text, overrides, FLEET_PREFIX)
    lines = _OverrideLines(source, index, [where for _, where in implicit], len(command_line))
    return member, [lines.diagnostic(d) for d in member.check.diagnostics]


def _merge(fleet_path: str, source: SourceMap, found: list[tuple[FleetMember, list[Diagnostic]]]) -> list[Diagnostic]:
    """Every robot's diagnostics, those inside a shared description once, with a note per robot that met it."""
    merged: dict[tuple, tuple[Diagnostic, list[Related]]] = {}
    for member, diagnostics in found:
        where = source.locate(robot_path(member.index, "name"))
        note = Related(where.path, where.line, where.column, f"met checking robot {member.entry.name or member.index}")
        for diagnostic in diagnostics:
            key = (diagnostic.path, diagnostic.line, diagnostic.column, diagnostic.code, diagnostic.message)
            kept = merged.setdefault(key, (diagnostic, []))
            if diagnostic.path != fleet_path:
                kept[1].append(note)
    return [replace(d, related=d.related + tuple(notes)) for d, notes in merged.values()]


def check_fleet_text(path: str, text: str, overrides: Sequence[str] = ()) -> FleetCheckResult:
    """Check a fleet file given as text: its own rules, then every robot; never raises for any input."""
    overrides = tuple(overrides)
    description, source, diagnostics = load_fleet(path, text)
    if description is None:
        return FleetCheckResult(path, text, None, sort_diagnostics(diagnostics), overrides)
    fleet = description.fleet_config
    found = [check_member(path, source, index, entry, overrides) for index, entry in enumerate(fleet.robot)]
    members = [member for member, _ in found]
    diagnostics += run_rules(FleetContext(fleet, source, members), stage="fleet")
    diagnostics += _merge(path, source, found)
    return FleetCheckResult(path, text, None, sort_diagnostics(diagnostics), overrides, fleet=fleet, members=members)
