"""Schema-free syntax tree of a protobuf text-format file, with token positions and comments.

The tokens are those of `google.protobuf.text_format.Tokenizer` (read in one regular-expression pass,
see `tokens`), and the tree follows its grammar:

    document := field*
    field    := NAME ( ":"? (block | list) | ":" scalar ) (";" | ",")?
    block    := "{" field* "}" | "<" field* ">"
    list     := "[" "]" | "[" item ("," item)* "]"       item := block | scalar
    scalar   := STRING+ | IDENTIFIER | NUMBER            (adjacent strings are concatenated)

The loader binds the tree to the schema; the formatter prints it back with its comments.
Lines and columns are 1-based; columns count characters.
"""

from __future__ import annotations

from dataclasses import dataclass, field as dataclass_field

import re

# Deeper nesting than this is refused (the schema nests four levels), so parsing never recurses far.
MAX_NESTING = 32
QUOTES = ("'", '"')
_OPENERS = {"{": "}", "<": ">"}


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


Value = Scalar | Block | ListValue


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


class SyntaxProblem(Exception):
    """The text is not protobuf text format; carries the position of the offending token."""

    def __init__(self, message: str, line: int, column: int, end_column: int | None = None):
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column
        self.end_column = end_column if end_column is not None else column + 1


# The tokens of protobuf's text_format.Tokenizer (identifier, number, and a string in either quote that
# ends at its closing quote or at the end of the line), then a comment, then any other single character;
# each after whitespace, taken whole (the possessive `*+`: never given back to the single-character case). One pass of this pattern over a line yields what the Tokenizer yields
# token by token, about thirty times faster.
_TOKEN = re.compile(r"""\s*+(?P<token>[a-zA-Z_][0-9a-zA-Z_+-]*"""
                    r"""|([0-9+-]|(\.[0-9]))[0-9a-zA-Z_.+-]*"""
                    r"""|'[^'\n\\]*((\\.)+[^'\n\\]*)*('|\\?$)"""
                    r"""|"[^"\n\\]*((\\.)+[^"\n\\]*)*("|\\?$)"""
                    r"""|\#.*|.)""")


def tokens(text: str):
    """(text, line, column) of every token and comment of the text, in order; 1-based positions."""
    for number, line in enumerate(text.split("\n"), start=1):
        for match in _TOKEN.finditer(line):
            yield match.group("token"), number, match.start("token") + 1


class _Stream:
    """Tokens without comments; comments are queued for the parser to attach."""

    def __init__(self, text: str):
        lines = text.split("\n")
        self.end = (len(lines), len(lines[-1]) + 1)
        self._tokens = tokens(text)
        self.comments: list[Comment] = []
        self.last_line = 0  # line of the last token consumed (0 before any)
        self.current: Token | None = None
        self._load()

    def _load(self) -> None:
        for text, line, column in self._tokens:
            if not text.startswith("#"):
                self.current = Token(text, line, column)
                return
            self.comments.append(Comment(text.rstrip(), line, column, trailing=line == self.last_line))
        self.current = None

    def advance(self) -> Token:
        token = self.current
        if token is None:
            raise self.problem("unexpected end of file")
        self.last_line = token.line
        self._load()
        return token
    def take_comments(self) -> list[Comment]:
        comments, self.comments = self.comments, []
        return comments

    def take_trailing(self) -> Comment | None:
        if self.comments and self.comments[0].trailing:
            return self.comments.pop(0)
        return None

    def looking_at(self, text: str) -> bool:
        return self.current is not None and self.current.text == text

    def problem(self, message: str) -> SyntaxProblem:
        token = self.current
        if token is None:
            return SyntaxProblem(message, *self.end)
        return SyntaxProblem(message, token.line, token.column, token.end_column)


def _describe(token: Token | None) -> str:
    if token is None:
        return "end of file"
    text = token.text if len(token.text) <= 40 else token.text[:37] + "..."
    return text if text[:1] in QUOTES else f'"{text}"'


def _is_name(text: str) -> bool:
    return text[:1].isalnum() or text[:1] == "_"


def _is_scalar(text: str) -> bool:
    return _is_name(text) or text[:1] in "+-" or text[:1] in QUOTES or (text[:1] == "." and len(text) > 1)


def _is_terminated(text: str) -> bool:
    """Whether a string token closes with an unescaped copy of its opening quote."""
    quote, index = text[0], 1
    while index < len(text):
        char = text[index]
        if char == "\\":
            index += 2
        elif char == quote:
            return index == len(text) - 1
        else:
            index += 1
    return False


class _Parser:
    def __init__(self, text: str):
        self.stream = _Stream(text)

    def document(self) -> Document:
        fields = self.fields(closer=None, depth=0)
        return Document(fields, self.stream.take_comments())

    def fields(self, closer: str | None, depth: int) -> list[Field]:
        stream = self.stream
        fields: list[Field] = []
        while True:
            token = stream.current
            if token is None:
                if closer is not None:
                    raise stream.problem(f'expected "{closer}" before the end of the file')
                return fields
            if closer is not None and token.text == closer:
                return fields
            fields.append(self.field(depth))

    def field(self, depth: int) -> Field:
        stream = self.stream
        previous_line = stream.last_line
        leading = stream.take_comments()
        name = stream.current
        first_line = leading[0].line if leading else name.line
        if name.text == "[":
            raise stream.problem("extension and Any fields ([...]) are not supported")
        if not _is_name(name.text):
            raise stream.problem(f"expected a field name, found {_describe(name)}")
        stream.advance()
        colon = stream.looking_at(":")
        if colon:
            stream.advance()
        if stream.current is None:
            raise stream.problem(f'expected a value for "{name.text}" before the end of the file')
        opener = stream.current.text
        if opener in _OPENERS:
            value: Value = self.block(depth + 1)
        elif opener == "[":
            value = self.list_value(depth + 1)
        elif not colon:
            raise stream.problem(f'expected ":" or "{{" after field name "{name.text}", found {_describe(stream.current)}')
        else:
            value = self.scalar()
        blank_before = previous_line > 0 and first_line - previous_line > 1
        field = Field(name, colon, value, leading, blank_before)
        if stream.looking_at(",") or stream.looking_at(";"):
            stream.advance()
        field.trailing = stream.take_trailing()
        return field

    def block(self, depth: int) -> Block:
        stream = self.stream
        if depth > MAX_NESTING:
            raise stream.problem(f"messages nested deeper than {MAX_NESTING} levels")
        open_token = stream.advance()
        closer = _OPENERS[open_token.text]
        trailing_open = stream.take_trailing()
        fields = self.fields(closer, depth)
        dangling = stream.take_comments()
        close = stream.advance()
        return Block(open_token, fields, close, trailing_open, dangling)

    def list_value(self, depth: int) -> ListValue:
        stream = self.stream
        open_token = stream.advance()
        items: list[Scalar | Block] = []
        if not stream.looking_at("]"):
            while True:
                if stream.current is None:
                    raise stream.problem('expected "]" before the end of the file')
                if stream.current.text in _OPENERS:
                    if depth + 1 > MAX_NESTING:
                        raise stream.problem(f"messages nested deeper than {MAX_NESTING} levels")
                    items.append(self.block(depth + 1))
                else:
                    items.append(self.scalar())
                if stream.looking_at("]"):
                    break
                if not stream.looking_at(","):
                    raise stream.problem(f'expected "," or "]" in a list, found {_describe(stream.current)}')
                stream.advance()
        inner = stream.take_comments()
        close = stream.advance()
        return ListValue(open_token, items, close, inner)

    def scalar(self) -> Scalar:
        stream = self.stream
        token = stream.current
        if token is None or not _is_scalar(token.text):
            raise stream.problem(f"expected a value, found {_describe(token)}")
        if token.text[:1] not in QUOTES:
            return Scalar([stream.advance()])
        tokens = []
        while stream.current is not None and stream.current.text[:1] in QUOTES:
            if not _is_terminated(stream.current.text):
                raise stream.problem("unterminated string (a string must close on the line it opens)")
            tokens.append(stream.advance())
        return Scalar(tokens)


def parse_syntax(text: str) -> Document:
    """Parse text into a syntax tree; raises SyntaxProblem at the first syntax error."""
    return _Parser(text).document()
