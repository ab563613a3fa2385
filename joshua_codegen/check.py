"""`joshuac check`: load a description, apply `--set` overrides, run every rule, collect diagnostics.

Load errors stop before the rules (a half-read description would only cause confusing
follow-up errors); override errors do not. When `has_errors` is False, `description` is valid
for every later stage: enum values, names, topics, ranges and required fields are checked.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from joshua_codegen.diagnostics import ERROR, Diagnostic, sort_diagnostics
from joshua_codegen.load import NOT_TEXT, load_text
from joshua_codegen.model import Robot
from joshua_codegen.overrides import OVERRIDE_PATH, apply_overrides
from joshua_codegen.rules import run_rules
from joshua_codegen.rules.context import RuleContext
from joshua_core.schema import RobotDescription
from joshua_codegen.source_file import SourceProblem, read_description

BYTE_ORDER_MARK = "\ufeff"


@dataclass
class CheckResult:
    path: str
    text: str
    description: RobotDescription | None  # with the overrides applied; None when it could not be loaded
    diagnostics: list[Diagnostic]
    overrides: tuple[str, ...] = field(default=())
    robot: Robot | None = None  # the planned model, when the description had no error before planning

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
        text = text[len(BYTE_ORDER_MARK):]
    nul = text.find("\0")
    if nul >= 0:
        line, column = _position(text, nul)
        problem = Diagnostic(path, line, column, NOT_TEXT, ERROR,
                             "the file contains a NUL character: is it a binary file?")
        return CheckResult(path, text, None, [problem], overrides)
    loaded = load_text(path, text)
    if loaded.description is None:
        return CheckResult(path, text, None, sort_diagnostics(loaded.diagnostics), overrides)
    description, source, diagnostics = apply_overrides(loaded.description, loaded.source_map, overrides)
    sources = CheckResult(path, text, description, [], overrides).sources
    context = RuleContext(description, source, sources, prefix)
    diagnostics += run_rules(context)
    if any(d.is_error for d in diagnostics):
        return CheckResult(path, text, description, sort_diagnostics(diagnostics), overrides)
    diagnostics += run_rules(context, stage="plan")
    return CheckResult(path, text, description, sort_diagnostics(diagnostics), overrides, context.robot)


def decode(path: str, data: bytes) -> tuple[str | None, list[Diagnostic]]:
    """UTF-8 text of a file's bytes, or an E008 diagnostic at the first byte that is not UTF-8."""
    try:
        return data.decode("utf-8"), []
    except UnicodeDecodeError as exc:
        good = data[:exc.start].decode("utf-8")
        line, column = _position(good, len(good))
        return None, [Diagnostic(path, line, column, NOT_TEXT, ERROR,
                                 f"the file is not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start})")]


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
