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

import re
from dataclasses import dataclass

from joshua_codegen.syntax_tree import (  # re-exported: the tree is part of this module's interface
    QUOTES,
    Block,
    Broken,
    Comment,
    Document,
    Field,
    ListValue,
    Scalar,
    SyntaxProblem,
    Token,
    Value,
)

# Deeper nesting than this is refused (the schema nests four levels), so parsing never recurses far.
MAX_NESTING = 32
_OPENERS = {"{": "}", "<": ">"}
_CLOSERS = frozenset(_OPENERS.values())


# The tokens of protobuf's text_format.Tokenizer (identifier, number, and a string in either quote that
# ends at its closing quote or at the end of the line), then a comment, then any other single character;
# each after whitespace, taken whole: never given back to the single-character case. `(?=(?P<space>\s*))(?P=space)`
# is the possessive `\s*+` of Python 3.11 written so that Python 3.10 reads it too (a lookahead is atomic,
# and the backreference consumes what it matched). One pass of this pattern over a line yields what the
# Tokenizer yields token by token, about thirty times faster.
_TOKEN = re.compile(
    r"""(?=(?P<space>\s*))(?P=space)(?P<token>[a-zA-Z_][0-9a-zA-Z_+-]*"""
    r"""|([0-9+-]|(\.[0-9]))[0-9a-zA-Z_.+-]*"""
    r"""|'[^'\n\\]*((\\.)+[^'\n\\]*)*('|\\?$)"""
    r"""|"[^"\n\\]*((\\.)+[^"\n\\]*)*("|\\?$)"""
    r"""|\#.*|.)"""
)


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
        self.previous: Token | None = None  # the last token consumed
        self.current: Token | None = None
        self.nesting = 0  # blocks opened and not closed by the tokens consumed
        self.line_starts: list[Token] = []  # the first token of every line that has one
        self.line_indent: dict[int, int] = {}  # line -> column of its first token
        self._load()

    def _load(self) -> None:
        for text, line, column in self._tokens:
            if not text.startswith("#"):
                self.current = Token(text, line, column)
                if line not in self.line_indent:
                    self.line_indent[line] = column
                    self.line_starts.append(self.current)
                return
            self.comments.append(Comment(text.rstrip(), line, column, trailing=line == self.last_line))
        self.current = None

    def advance(self) -> Token:
        token = self.current
        if token is None:
            raise self.problem("unexpected end of file")
        self.last_line = token.line
        self.previous = token
        if token.text in _OPENERS:
            self.nesting += 1
        elif token.text in _CLOSERS:
            self.nesting -= 1
        self._load()
        return token

    def advance_quietly(self) -> None:
        """Advance, dropping the comments met (while skipping a broken field)."""
        if self.current is not None:
            self.advance()
        self.comments.clear()

    def take_comments(self) -> list[Comment]:
        comments, self.comments = self.comments, []
        return comments

    def take_trailing(self) -> Comment | None:
        if self.comments and self.comments[0].trailing:
            return self.comments.pop(0)
        return None

    def starts_line(self) -> bool:
        """Whether the current token is the first of its line."""
        return self.current is not None and self.current.line != self.last_line

    def looking_at(self, text: str) -> bool:
        return self.current is not None and self.current.text == text

    def problem(self, message: str) -> SyntaxProblem:
        token = self.current
        if token is None:
            return SyntaxProblem(message, *self.end, at_end=True)
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


@dataclass
class BlockTrace:
    """Where a block opened and closed (`close` None while open), for finding an unclosed one."""

    name: Token  # the field name before it (its opening brace for a block in a list)
    open: Token
    close: Token | None = None
    ended_before: Token | None = None  # when closed by indentation: the token it ended before


class GiveUp(Exception):
    """Recovery found no place to resume parsing; the problems already collected stand."""


class Parser:
    """Recursive-descent parser. With `recover`, a problem in a field of a top-level block is collected
    and parsing resumes at the next field of that block (`syntax_recovery.py` drives it); blocks whose
    opening brace is in `implicit_closes` end before the first line indented like their opening line."""

    def __init__(self, text: str, recover: bool = False, implicit_closes: dict | None = None):
        self.stream = _Stream(text)
        self.recover = recover
        self.implicit_closes = implicit_closes or {}
        self.problems: list[SyntaxProblem] = []
        self.traces: list[BlockTrace] = []
        self.closed_by_indent = False  # the block being parsed ended by indentation, not by its closer

    def document(self) -> Document:
        fields = self.fields(closer=None, depth=0)
        return Document(fields, self.stream.take_comments())

    def fields(self, closer: str | None, depth: int, limit: int | None = None) -> list[Field]:
        stream = self.stream
        fields: list[Field] = []
        while True:
            token = stream.current
            if token is None:
                if closer is not None:
                    raise stream.problem(f'expected "{closer}" before the end of the file')
                return fields
            if (
                limit is not None
                and stream.starts_line()
                and (token.column < limit or (token.column == limit and token.text != closer))
            ):
                self.closed_by_indent = True  # a closer further left belongs to an outer block
                return fields
            if closer is not None and token.text == closer:
                return fields
            if self.recover and depth == 1:
                fields.append(self.recovering_field(closer, depth))
            else:
                fields.append(self.field(depth))

    def recovering_field(self, closer: str | None, depth: int) -> Field:
        """A field, or a Broken placeholder after collecting its problem and skipping to the next field."""
        stream = self.stream
        first = stream.current
        try:
            return self.field(depth)
        except SyntaxProblem as problem:
            if problem.at_end:
                raise
            self.problems.append(problem)
            self.skip_to_field(closer, depth, problem.line)
            return Field(first, False, Broken(first, stream.previous or first))

    def skip_to_field(self, closer: str | None, depth: int, after_line: int) -> None:
        """Skip to the next line starting with a field name at this depth, or to the block's closer."""
        stream = self.stream
        stream.advance_quietly()
        while stream.current is not None:
            if stream.nesting < depth:
                raise GiveUp()
            if stream.nesting == depth:
                token = stream.current
                if token.text == closer:
                    return
                if token.line > after_line and stream.starts_line() and _is_name(token.text):
                    return
            stream.advance_quietly()
        raise stream.problem(f'expected "{closer}" before the end of the file')

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
            value: Value = self.block(depth + 1, name)
        elif opener == "[":
            value = self.list_value(depth + 1)
        elif not colon:
            raise stream.problem(
                f'expected ":" or "{{" after field name "{name.text}", found {_describe(stream.current)}'
            )
        else:
            value = self.scalar()
        blank_before = previous_line > 0 and first_line - previous_line > 1
        field = Field(name, colon, value, leading, blank_before)
        if stream.looking_at(",") or stream.looking_at(";"):
            stream.advance()
        field.trailing = stream.take_trailing()
        return field

    def block(self, depth: int, name: Token | None = None) -> Block:
        stream = self.stream
        if depth > MAX_NESTING:
            raise stream.problem(f"messages nested deeper than {MAX_NESTING} levels")
        open_token = stream.advance()
        trace = BlockTrace(name or open_token, open_token)
        self.traces.append(trace)
        closer = _OPENERS[open_token.text]
        trailing_open = stream.take_trailing()
        limit = self.implicit_closes.get((open_token.line, open_token.column))
        fields = self.fields(closer, depth, limit)
        dangling = stream.take_comments()
        if not self.closed_by_indent:
            close = stream.advance()
        else:  # closed by indentation (recovery): an empty token just after the last one
            self.closed_by_indent = False
            trace.ended_before = stream.current
            last = stream.previous
            close = Token("", last.line, last.end_column)
            stream.nesting -= 1
        trace.close = close
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
    return Parser(text).document()
