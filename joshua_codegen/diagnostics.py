"""The Diagnostic record and its three printed forms: text (for people), JSON and GitHub annotations.

Positions are 1-based; columns count characters; `end_column` is one past the last character.

JSON form (`format_json`), stable across releases of the same `version`:

    {
      "version": 1,
      "diagnostics": [
        {"path": "robot.pbtxt", "line": 12, "column": 5, "end_line": 12, "end_column": 29,
         "code": "E301", "severity": "error", "message": "...",
         "related": [{"path": "robot.pbtxt", "line": 4, "column": 5, "message": "publisher declared here"}]}
      ],
      "summary": {"errors": 1, "warnings": 0}
    }

`end_line`/`end_column` are null when unknown; diagnostics are sorted by path, line, column, code.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass

ERROR = "error"
WARNING = "warning"
JSON_FORMAT_VERSION = 1
# Longest source line echoed under a diagnostic; longer lines are cut around the column.
MAX_ECHOED_LINE = 200


@dataclass(frozen=True)
class Related:
    path: str
    line: int
    column: int
    message: str


@dataclass(frozen=True)
class Diagnostic:
    path: str
    line: int
    column: int
    code: str
    severity: str  # "error" | "warning"
    message: str
    end_line: int | None = None
    end_column: int | None = None
    related: tuple[Related, ...] = ()

    @property
    def is_error(self) -> bool:
        return self.severity == ERROR


def sort_diagnostics(diags: Iterable[Diagnostic]) -> list[Diagnostic]:
    """By path, line, column and code (message last, so the order is total)."""
    return sorted(diags, key=lambda d: (d.path, d.line, d.column, d.code, d.message))


def _plural(count: int, word: str) -> str:
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


def summary(diags: Iterable[Diagnostic]) -> str:
    """`2 errors, 1 warning`."""
    diags = list(diags)
    errors = sum(1 for d in diags if d.is_error)
    return f"{_plural(errors, 'error')}, {_plural(len(diags) - errors, 'warning')}"


def _snippet(
    lines: list[str] | None, line: int, column: int, end_line: int | None, end_column: int | None
) -> list[str]:
    """The source line and a caret under the column (tildes over the rest of a one-line range)."""
    if lines is None:
        return []
    if not 1 <= line <= len(lines):
        return []
    text = lines[line - 1].rstrip("\r")
    if not text.strip():
        return []
    start = max(column - 1, 0)
    width = 1
    if end_line == line and end_column is not None and end_column > column:
        width = end_column - column
    offset = 0
    if len(text) > MAX_ECHOED_LINE:
        offset = max(0, min(start - MAX_ECHOED_LINE // 2, len(text) - MAX_ECHOED_LINE))
        text = text[offset : offset + MAX_ECHOED_LINE]
        start -= offset
    start = min(start, len(text))
    width = max(1, min(width, len(text) - start))
    if not text.isprintable():
        text = "".join(c if c.isprintable() or c == "\t" else "?" for c in text)
    pad = "".join("\t" if c == "\t" else " " for c in text[:start]) if "\t" in text else " " * start
    return [text, pad + "^" + "~" * (width - 1)]


def _one_line(text: str) -> str:
    """Text with control characters escaped (`\\n`, `\\x01`), so a message stays on one line."""
    if all(c.isprintable() for c in text):
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def format_text(diags: Iterable[Diagnostic], sources: dict[str, str]) -> str:
    """`path:line:col: error[CODE]: message`, the source line and a caret, notes, then a summary line."""
    diags = sort_diagnostics(diags)
    lines_of: dict[str, list[str] | None] = {}  # each source split once: linear in the diagnostics

    def lines(path: str) -> list[str] | None:
        if path not in lines_of:
            source = sources.get(path)
            lines_of[path] = source.split("\n") if source is not None else None
        return lines_of[path]

    out: list[str] = []
    for d in diags:
        out.append(f"{_one_line(d.path)}:{d.line}:{d.column}: {d.severity}[{d.code}]: {_one_line(d.message)}")
        out.extend(_snippet(lines(d.path), d.line, d.column, d.end_line, d.end_column))
        for note in d.related:
            out.append(f"{_one_line(note.path)}:{note.line}:{note.column}: note: {_one_line(note.message)}")
            out.extend(_snippet(lines(note.path), note.line, note.column, None, None))
    out.append(summary(diags))
    return "\n".join(out) + "\n"


def _as_dict(d: Diagnostic) -> dict:
    return {
        "path": d.path,
        "line": d.line,
        "column": d.column,
        "end_line": d.end_line,
        "end_column": d.end_column,
        "code": d.code,
        "severity": d.severity,
        "message": d.message,
        "related": [{"path": r.path, "line": r.line, "column": r.column, "message": r.message} for r in d.related],
    }


def format_json(diags: Iterable[Diagnostic]) -> str:
    """The documented JSON form (see the module docstring), ending with a newline."""
    diags = sort_diagnostics(diags)
    errors = sum(1 for d in diags if d.is_error)
    document = {
        "version": JSON_FORMAT_VERSION,
        "diagnostics": [_as_dict(d) for d in diags],
        "summary": {"errors": errors, "warnings": len(diags) - errors},
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def format_github(diags: Iterable[Diagnostic]) -> str:
    """One GitHub Actions workflow command per diagnostic: `::error file=...,line=...,col=...,title=CODE::message`."""
    out = []
    for d in sort_diagnostics(diags):
        props = [f"file={_escape_property(d.path)}", f"line={d.line}", f"col={d.column}"]
        if d.end_line is not None and d.end_column is not None:
            props.append(f"endLine={d.end_line}")
            props.append(f"endColumn={max(d.end_column - 1, d.column)}")
        props.append(f"title={_escape_property(d.code)}")
        message = d.message
        for note in d.related:
            message += f" ({note.message}: {note.path}:{note.line}:{note.column})"
        out.append(f"::{d.severity} {','.join(props)}::{_escape_data(message)}")
    return "".join(line + "\n" for line in out)
