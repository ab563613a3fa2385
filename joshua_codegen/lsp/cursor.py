"""What is written at a cursor: the message whose fields are there, and whether a field name or a value is due.

Read from the tokens before the cursor alone (`syntax.tokens`), so it works in text that does not parse,
as text being typed seldom does: blocks opened and not closed, a field name without its value yet.
"""

from __future__ import annotations

from dataclasses import dataclass

from google.protobuf.descriptor import Descriptor, FieldDescriptor

from joshua_codegen.syntax import tokens
from joshua_core.schema import RobotDescription

NAME, AFTER_NAME, VALUE, LIST = "name", "after name", "value", "list"
_OPENERS = {"{": "}", "<": ">"}
_CLOSERS = frozenset(_OPENERS.values())


@dataclass(frozen=True)
class Word:
    """A token at the cursor: its text and 1-based position."""

    text: str
    line: int
    column: int

    @property
    def end_column(self) -> int:
        return self.column + len(self.text)


@dataclass
class Cursor:
    message: Descriptor | None  # the message whose fields are written here (None inside an unknown field)
    expects: str  # NAME (a field name is due) or VALUE (a value of `field`)
    field: FieldDescriptor | None  # for VALUE: the field whose value is due
    word: Word | None  # the token under or just before the cursor, if any
    prefix: str  # the part of `word` before the cursor


@dataclass
class _Frame:
    message: Descriptor | None
    resume: str  # the state after the block closes
    list_field: FieldDescriptor | None  # the field of the list the block is an item of


class _Reader:
    """The tokens' state machine: a stack of open blocks and what is due next."""

    def __init__(self):
        self.frames = [_Frame(RobotDescription.DESCRIPTOR, NAME, None)]
        self.state = NAME
        self.field: FieldDescriptor | None = None  # the last field name read
        self.list_field: FieldDescriptor | None = None  # the field of the open [...] list
        self.line = 0  # the line of the last token read

    def open_block(self, field: FieldDescriptor | None, resume: str) -> None:
        message = field.message_type if field is not None else None
        self.frames.append(_Frame(message, resume, self.list_field if resume == LIST else None))
        self.state = NAME

    def starts_field(self, text: str, line: int) -> bool:
        """Whether a token ends an unfinished value or list: a field name of this message starting a later line."""
        message = self.frames[-1].message
        return line > self.line and message is not None and text in message.fields_by_name

    def feed(self, text: str, line: int) -> None:
        state = self.state
        if state in (VALUE, LIST) and self.starts_field(text, line):
            state = self.state = NAME
        self.line = line
        if text in _CLOSERS:
            if len(self.frames) > 1:
                frame = self.frames.pop()
                self.state, self.list_field = frame.resume, frame.list_field
            return
        if state == LIST:
            if text in _OPENERS:
                self.open_block(self.list_field, LIST)
            elif text == "]":
                self.state = NAME
            return
        if state == AFTER_NAME and text == ":":
            self.state = VALUE
        elif state in (AFTER_NAME, VALUE) and text in _OPENERS:
            self.open_block(self.field, NAME)
        elif state in (AFTER_NAME, VALUE) and text == "[":
            self.list_field, self.state = self.field, LIST
        elif state == VALUE:
            self.state = NAME
        elif text[:1].isalpha() or text[:1] == "_":
            message = self.frames[-1].message
            self.field = message.fields_by_name.get(text) if message is not None else None
            self.state = AFTER_NAME

    def cursor(self, word: Word | None, prefix: str) -> Cursor:
        message = self.frames[-1].message
        if self.state == LIST:
            return Cursor(message, VALUE, self.list_field, word, prefix)
        if self.state == VALUE:
            return Cursor(message, VALUE, self.field, word, prefix)
        return Cursor(message, NAME, None, word, prefix)


def cursor_at(text: str, line: int, column: int) -> Cursor:
    """The cursor before the character at 1-based `line`, `column` (a column past the line's end is its end)."""
    reader = _Reader()
    for token, token_line, token_column in tokens(text):
        if (token_line, token_column) >= (line, column):
            break
        if token.startswith("#"):
            if token_line == line:  # in a comment: nothing is due
                return Cursor(None, NAME, None, None, "")
            continue
        end = token_column + len(token)
        if token_line == line and end >= column:  # the cursor is inside this token or just after it
            word = Word(token, token_line, token_column)
            if token in _OPENERS or token in _CLOSERS or token in ":,;[]":
                reader.feed(token, token_line)
                return reader.cursor(None, "")
            if reader.state in (VALUE, LIST) and reader.starts_field(token, token_line):
                reader.state = NAME
            return reader.cursor(word, token[: column - token_column])
        reader.feed(token, token_line)
    return reader.cursor(None, "")


def word_at(text: str, line: int, column: int) -> Word | None:
    """The token that holds the character at 1-based `line`, `column`, comments excluded."""
    for token, token_line, token_column in tokens(text):
        if token_line > line:
            return None
        if token_line == line and token_column <= column < token_column + len(token):
            return None if token.startswith("#") else Word(token, token_line, token_column)
    return None
