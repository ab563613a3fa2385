"""`joshuac check`: load a description, apply `--set` overrides, run every rule, collect diagnostics.

Load errors inside nodes do not stop the rules: they check every node that was read whole (the
others are "unknown", see rules/__init__.py). Load errors elsewhere (robot settings, the file root)
stop before the rules, since every rule reads those. Override errors do not stop them. When `has_errors` is False, `description` is valid
for every later stage: enum values, names, topics, ranges and required fields are checked.
A fleet file (its first field is `fleet_config`) is checked by fleet/check.py instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from joshua_codegen.diagnostics import ERROR, Diagnostic, sort_diagnostics
from joshua_codegen.fleet.load import is_fleet_text
from joshua_codegen.load import NOT_TEXT, LoadResult, load_text
from joshua_codegen.model import Robot
from joshua_codegen.overrides import OVERRIDE_PATH, UNKNOWN_OVERRIDE_TARGET, apply_overrides
from joshua_codegen.rules import run_rules
from joshua_codegen.rules.context import RuleContext
from joshua_codegen.source_file import SourceProblem, read_description
from joshua_core.schema import RobotDescription

BYTE_ORDER_MARK = "\ufeff"


@dataclass
class CheckResult:
    path: str
    text: str
    description: RobotDescription | None  # with the overrides applied; None when it could not be loaded
    diagnostics: list[Diagnostic]
    overrides: tuple[str, ...] = field(default=())
    robot: Robot | None = None  # the planned model, when the description had no error before planning
    context: RuleContext | None = None  # what the rules read (topic index, names), when they ran

    @property
    def has_errors(self) -> bool:
        return any(d.severity == ERROR for d in self.diagnostics)

    @property
    def sources(self) -> dict[str, str]:
        """Texts for `format_text`: the file, and the overrides as the lines of `--set`."""
        sources = {self.path: self.text}
        if self.overrides:
            sources[OVERRIDE_PATH] = "\n".join(self.overrides)
        return sources


def _position(text: str, index: int) -> tuple[int, int]:
    line = text.count("\n", 0, index) + 1
    return line, index - (text.rfind("\n", 0, index) + 1) + 1


def check_text(path: str, text: str, overrides: Sequence[str] = (), prefix: str | None = None) -> CheckResult:
    """Check one description given as text; never raises for any text or override.

    `prefix` is where the output will live on the robot (`build --prefix`); limits that depend on it
    (command line lengths) are checked for it, else for the default."""
    overrides = tuple(overrides)
    if text.startswith(BYTE_ORDER_MARK):
        text = text[len(BYTE_ORDER_MARK) :]
    nul = text.find("\0")
    if nul >= 0:
        line, column = _position(text, nul)
        problem = Diagnostic(
            path, line, column, NOT_TEXT, ERROR, "the file contains a NUL character: is it a binary file?"
        )
        return CheckResult(path, text, None, [problem], overrides)
    if is_fleet_text(text):
        from joshua_codegen.fleet.check import check_fleet_text

        return check_fleet_text(path, text, overrides)
    loaded = load_text(path, text)
    if loaded.description is None and loaded.partial is None:
        return CheckResult(path, text, None, sort_diagnostics(loaded.diagnostics), overrides)
    if loaded.description is None:
        return _check_partial(path, text, loaded, overrides, prefix)
    description, source, diagnostics = apply_overrides(loaded.description, loaded.source_map, overrides)
    sources = CheckResult(path, text, description, [], overrides).sources
    context = RuleContext(description, source, sources, prefix)
    diagnostics += run_rules(context)
    if any(d.is_error for d in diagnostics):
        return CheckResult(path, text, description, sort_diagnostics(diagnostics), overrides, context=context)
    diagnostics += run_rules(context, stage="plan")
    return CheckResult(path, text, description, sort_diagnostics(diagnostics), overrides, context.robot, context)


def _check_partial(
    path: str, text: str, loaded: LoadResult, overrides: tuple[str, ...], prefix: str | None
) -> CheckResult:
    """The load errors plus what the rules find in the nodes that were read whole; no description
    comes out (later stages need a valid one). An override naming an unknown node is not reported."""
    partial, source, diagnostics = apply_overrides(loaded.partial, loaded.source_map, overrides)
    if loaded.unknown_nodes:
        diagnostics = [d for d in diagnostics if d.code != UNKNOWN_OVERRIDE_TARGET]
    sources = CheckResult(path, text, partial, [], overrides).sources
    context = RuleContext(partial, source, sources, prefix, loaded.unknown_nodes)
    diagnostics = loaded.diagnostics + diagnostics + run_rules(context)
    return CheckResult(path, text, None, sort_diagnostics(diagnostics), overrides, context=context)


def decode(path: str, data: bytes) -> tuple[str | None, list[Diagnostic]]:
    """UTF-8 text of a file's bytes, or an E008 diagnostic at the first byte that is not UTF-8."""
    try:
        return data.decode("utf-8"), []
    except UnicodeDecodeError as exc:
        good = data[: exc.start].decode("utf-8")
        line, column = _position(good, len(good))
        return None, [
            Diagnostic(
                path,
                line,
                column,
                NOT_TEXT,
                ERROR,
                f"the file is not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start})",
            )
        ]


def check_file(path: str, overrides: Sequence[str] = (), prefix: str | None = None) -> CheckResult:
    """Check one description file; an unreadable, oversized, non-regular or non-UTF-8 file gives a
    diagnostic, never an exception or a hang."""
    try:
        data = read_description(path)
    except SourceProblem as problem:
        return CheckResult(path, "", None, [problem.diagnostic], tuple(overrides))
    text, problems = decode(path, data)
    if text is None:
        shown = data.decode("utf-8", errors="replace")
        return CheckResult(path, shown, None, problems, tuple(overrides))
    return check_text(path, text, overrides, prefix)
