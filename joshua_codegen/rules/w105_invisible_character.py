"""W105 invisible-character: a string holds an invisible character that changes how it looks.

What it checks:
    No string (names, topics, paths, programs, args, environment, ...) contains a Unicode format
    character (category Cf): bidirectional overrides, embeddings and isolates (U+202A-U+202E,
    U+2066-U+2069, U+200E, U+200F, U+061C), zero-width characters (U+200B-U+200D, U+2060),
    U+FEFF, soft hyphens and tag characters. The position is the character itself.

Why it matters:
    Such characters are invisible or reorder the text around them, so a value does not read as
    what it is: `/dev/ttyUSB0` can name another device, `rm` another program, and a reviewer of
    the file or of the generated units sees something else than what runs.

Example:
    node {
      serial_port: "/dev/ttyUSB‮0"   # warning: serial_port contains U+202E RIGHT-TO-LEFT OVERRIDE
    }
"""

import unicodedata

from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding, strings_of

CODE = "W105"
NAME = "invisible-character"
SEVERITY = WARNING
STAGE = "check"


def _invisible(text: str) -> list[str]:
    return [char for char in text if unicodedata.category(char) == "Cf"]


class _Columns:
    """Exact columns of characters in the written text, each source split into lines once."""

    def __init__(self, sources: dict[str, str]):
        self.sources = sources
        self.lines: dict[str, list[str]] = {}

    def of(self, location, char: str) -> int | None:
        """Column of `char` in the text written at `location`, or None when it was written as an escape."""
        if location is None or location.path not in self.sources:
            return None
        if location.path not in self.lines:
            self.lines[location.path] = self.sources[location.path].split("\n")
        lines = self.lines[location.path]
        if not 1 <= location.line <= len(lines):
            return None
        text = lines[location.line - 1]
        end = location.end_column - 1 if location.end_line == location.line and location.end_column else len(text)
        index = text.find(char, location.column - 1, max(end, location.column - 1))
        if index < 0:
            index = text.find(char, location.column - 1)
        return index + 1 if index >= 0 else None


def check(ctx):
    columns = _Columns(ctx.sources)
    for path, what, text in strings_of(ctx.description):
        found = _invisible(text)
        if not found:
            continue
        char = found[0]
        name = unicodedata.name(char, "FORMAT CHARACTER")
        more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
        message = (
            f"{what} contains U+{ord(char):04X} {name}{more} at character {text.index(char) + 1}, "
            "an invisible character that changes how the text looks; remove it"
        )
        column = columns.of(ctx.source.get(path), char)
        yield Finding(path, message, column=column, end_column=column + 1 if column else None)
