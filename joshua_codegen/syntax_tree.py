"""The syntax tree of a protobuf text-format file: tokens, comments, values, fields and the problem type.

Built by `syntax.py`; lines and columns are 1-based and count characters.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dataclass_field

QUOTES = ("'", '"')


@dataclass(frozen=True)
class Token:
    text: str
    line: int
    column: int

    @property
    def end_column(self) -> int:
        """Column just past the token (tokens never span lines)."""
        return self.column + len(self.text)


@dataclass(frozen=True)
class Comment:
    text: str
    line: int
    column: int
    # True when the comment follows another token on the same line.
    trailing: bool


@dataclass
class Scalar:
    tokens: list[Token]

    @property
    def first(self) -> Token:
        return self.tokens[0]

    @property
    def last(self) -> Token:
        return self.tokens[-1]

    @property
    def is_string(self) -> bool:
        return self.tokens[0].text[:1] in QUOTES


@dataclass
class Block:
    open: Token
    fields: list[Field]
    close: Token
    trailing_open: Comment | None = None  # comment on the line of the opening brace
    dangling: list[Comment] = dataclass_field(default_factory=list)  # comments before the close

    @property
    def first(self) -> Token:
        return self.open

    @property
    def last(self) -> Token:
        return self.close


@dataclass
class ListValue:
    open: Token
    items: list[Scalar | Block]
    close: Token
    inner_comments: list[Comment] = dataclass_field(default_factory=list)

    @property
    def first(self) -> Token:
        return self.open

    @property
    def last(self) -> Token:
        return self.close


@dataclass
class Field:
    name: Token
    colon: bool
    value: Value
    leading: list[Comment] = dataclass_field(default_factory=list)  # own-line comments above
    blank_before: bool = False  # an empty line separated it from what came before
    trailing: Comment | None = None  # comment after the value, on the same line


@dataclass
class Document:
    fields: list[Field]
    dangling: list[Comment]  # comments after the last field


@dataclass
class Broken:
    """A field whose value could not be parsed; parsing went on after it (see `syntax_recovery.py`)."""

    first: Token
    last: Token


Value = Scalar | Block | ListValue | Broken


class SyntaxProblem(Exception):
    """The text is not protobuf text format; carries the position of the offending token.

    `at_end` is True when the end of the file was reached; `notes` are (line, column, message) pointing
    at other places that explain it."""

    def __init__(
        self,
        message: str,
        line: int,
        column: int,
        end_column: int | None = None,
        at_end: bool = False,
        notes: tuple[tuple[int, int, str], ...] = (),
    ):
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column
        self.end_column = end_column if end_column is not None else column + 1
        self.at_end = at_end
        self.notes = notes
