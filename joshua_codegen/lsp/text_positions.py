"""Positions between joshuac (1-based lines, columns in characters, lines split at "\\n") and an LSP client
(0-based, columns in the code units the client chose: UTF-16 by default)."""

from __future__ import annotations

from collections.abc import Callable

from lsprotocol import types

Units = Callable[[str], int]  # the number of client code units of a string


class Lines:
    """One document's text split as joshuac splits it, with conversions to and from client positions."""

    def __init__(self, text: str, units: Units):
        self.text = text
        self.lines = text.split("\n")
        self.units = units

    def line(self, index: int) -> str:
        """The 0-based index-th line ("" past the end)."""
        return self.lines[index] if 0 <= index < len(self.lines) else ""

    def position(self, line: int, column: int) -> types.Position:
        """The client position of a joshuac line and column (1-based; clamped to the text)."""
        index = min(max(line - 1, 0), len(self.lines) - 1)
        text = self.lines[index]
        return types.Position(index, self.units(text[: max(column - 1, 0)]))

    def range(self, line: int, column: int, end_line: int | None, end_column: int | None) -> types.Range:
        """A client range; one character wide when joshuac knows only the start."""
        if end_line is None or end_column is None or (end_line, end_column) <= (line, column):
            end_line, end_column = line, column + 1
        return types.Range(self.position(line, column), self.position(end_line, end_column))

    def column(self, position: types.Position) -> int:
        """The 0-based character index in its line of a client position."""
        text = self.line(position.line)
        count = 0
        for index, char in enumerate(text):
            if count >= position.character:
                return index
            count += self.units(char)
        return len(text)

    def offset(self, position: types.Position) -> int:
        """The character offset in the text of a client position."""
        line = min(position.line, len(self.lines) - 1)
        return sum(len(text) + 1 for text in self.lines[:line]) + self.column(position)
