"""Loader: .pbtxt text to a RobotDescription plus the source position of every field and value.

It binds the syntax tree of `syntax.py` to the schema and reports every unknown field, bad value
and repeated field at once (E002-E005); a syntax error (E001) ends parsing. What it accepts,
`google.protobuf.text_format.Parse` accepts too, with the same result; it is stricter in three ways:
a singular field may be written only once, enum numbers must name a value, and map keys are unique.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass

from google.protobuf import text_encoding, text_format
from google.protobuf.descriptor import Descriptor, FieldDescriptor

from joshua_codegen.diagnostics import ERROR, Diagnostic, Related
from joshua_codegen.positions import Location, Path, SourceMap
from joshua_codegen.schema import RobotConfig, RobotDescription
from joshua_codegen.syntax import Block, Field, ListValue, Scalar, SyntaxProblem, Token, parse_syntax

SYNTAX_ERROR = "E001"
UNKNOWN_FIELD = "E002"
INVALID_VALUE = "E003"
UNKNOWN_ENUM_VALUE = "E004"
DUPLICATE_FIELD = "E005"
MISSING_ROBOT_CONFIG = "E006"
UNREADABLE_FILE = "E007"
NOT_TEXT = "E008"

# Integer literals longer than this are refused before conversion (uint64 needs at most 20 digits).
MAX_INTEGER_DIGITS = 64
SUGGESTION_CUTOFF = 0.6
_C_OCTAL = re.compile(r"-?0\d+$")
# Escapes text format defines; any other backslash sequence is refused rather than kept literally.
_ESCAPE = re.compile(r"\\(?:[abfnrtv\\'\"]|[0-7]{1,3}|x[0-9A-Fa-f]{1,2}|u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8})")
_INTEGER_RANGES = {
    FieldDescriptor.TYPE_INT32: ("a 32-bit integer", -(2**31), 2**31 - 1),
    FieldDescriptor.TYPE_SINT32: ("a 32-bit integer", -(2**31), 2**31 - 1),
    FieldDescriptor.TYPE_SFIXED32: ("a 32-bit integer", -(2**31), 2**31 - 1),
    FieldDescriptor.TYPE_UINT32: ("an unsigned 32-bit integer", 0, 2**32 - 1),
    FieldDescriptor.TYPE_FIXED32: ("an unsigned 32-bit integer", 0, 2**32 - 1),
    FieldDescriptor.TYPE_INT64: ("a 64-bit integer", -(2**63), 2**63 - 1),
    FieldDescriptor.TYPE_SINT64: ("a 64-bit integer", -(2**63), 2**63 - 1),
    FieldDescriptor.TYPE_SFIXED64: ("a 64-bit integer", -(2**63), 2**63 - 1),
    FieldDescriptor.TYPE_UINT64: ("an unsigned 64-bit integer", 0, 2**64 - 1),
    FieldDescriptor.TYPE_FIXED64: ("an unsigned 64-bit integer", 0, 2**64 - 1),
}
_FLOATS = (FieldDescriptor.TYPE_DOUBLE, FieldDescriptor.TYPE_FLOAT)


@dataclass
class LoadResult:
    description: RobotDescription | None  # None when any load error was found
    source_map: SourceMap
    diagnostics: list[Diagnostic]


class ValueProblem(ValueError):
    """A scalar that does not fit its field; the message says why."""


def suggest(name: str, candidates, *, upper: bool = False) -> str | None:
    """The closest candidate to a misspelt name, or None."""
    candidates = list(candidates)
    if upper:
        matches = difflib.get_close_matches(name.upper(), candidates, n=1, cutoff=SUGGESTION_CUTOFF)
    else:
        matches = difflib.get_close_matches(name, candidates, n=1, cutoff=SUGGESTION_CUTOFF)
    return matches[0] if matches else None


def _parse_integer(text: str) -> int:
    """Integer literal as text format reads it: decimal, 0x hex, C-style 0 octal."""
    if len(text) > MAX_INTEGER_DIGITS:
        raise ValueError(text)
    if _C_OCTAL.match(text):
        text = text.replace("0", "0o", 1)
    return int(text, 0)


def _check_escapes(body: str) -> None:
    index = body.find("\\")
    while index >= 0:
        match = _ESCAPE.match(body, index)
        if match is None:
            escape = body[index:index + 2]
            raise ValueProblem(f'invalid escape "{escape}" in a string (write "\\\\" for a backslash)')
        index = body.find("\\", match.end())


def unquote(scalar: Scalar) -> bytes:
    """The bytes of a (possibly multi-token) string literal; ValueProblem for a bad escape."""
    parts = []
    for token in scalar.tokens:
        body = token.text[1:-1]
        _check_escapes(body)
        try:
            parts.append(text_encoding.CUnescape(body))
        except ValueError as exc:
            raise ValueProblem(f"invalid escape sequence in string {token.text}: {exc}") from None
    return b"".join(parts)


def _shown(scalar: Scalar) -> str:
    text = " ".join(t.text for t in scalar.tokens)
    return text if len(text) <= 40 else text[:37] + "..."


def decode_string(scalar: Scalar, name: str = "the field") -> str:
    """A string literal's value; ValueProblem for a non-string token, a bad escape or invalid UTF-8."""
    if not scalar.is_string:
        raise ValueProblem(f"{name} takes a quoted string, got {_shown(scalar)}")
    try:
        return unquote(scalar).decode("utf-8")
    except UnicodeDecodeError:
        raise ValueProblem("string is not valid UTF-8 (write non-ASCII characters directly)") from None


def parse_scalar(field: FieldDescriptor, scalar: Scalar):
    """The Python value of a scalar for a non-enum field; ValueProblem when it does not fit."""
    kind = field.type
    if kind == FieldDescriptor.TYPE_STRING:
        return decode_string(scalar, field.name)
    if kind == FieldDescriptor.TYPE_BYTES:
        if not scalar.is_string:
            raise ValueProblem(f"{field.name} takes a quoted string, got {_shown(scalar)}")
        return unquote(scalar)
    text = scalar.first.text
    if scalar.is_string:
        raise ValueProblem(f"{field.name} takes {_kind_name(field)}, not a string; remove the quotes")
    if kind in _INTEGER_RANGES:
        described, low, high = _INTEGER_RANGES[kind]
        try:
            value = _parse_integer(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes {described}, got {_shown(scalar)}") from None
        if not low <= value <= high:
            raise ValueProblem(f"{field.name} takes {described} ({low} to {high}), got {_shown(scalar)}")
        return value
    if kind in _FLOATS:
        try:
            return text_format.ParseFloat(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes a number, got {_shown(scalar)}") from None
    if kind == FieldDescriptor.TYPE_BOOL:
        try:
            return text_format.ParseBool(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes true or false, got {_shown(scalar)}") from None
    raise ValueProblem(f"{field.name} has an unsupported type")


def _kind_name(field: FieldDescriptor) -> str:
    if field.type in _FLOATS:
        return "a number"
    if field.type == FieldDescriptor.TYPE_BOOL:
        return "true or false"
    return "an integer"


def enum_names(field: FieldDescriptor) -> list[str]:
    """The enum's value names, without its *_UNSPECIFIED zero value."""
    return [v.name for v in field.enum_type.values if v.number != 0]


def parse_enum(field: FieldDescriptor, text: str) -> tuple[int | None, str]:
    """(number, "") for a valid enum name or number, else (None, the reason)."""
    enum = field.enum_type
    named = enum.values_by_name.get(text)
    if named is not None:
        return named.number, ""
    try:
        number = int(text, 0)
    except ValueError:
        number = None
    if number is not None:
        # Compared value by value: upb's values_by_number wraps numbers to 32 bits (2**32 + 1 finds 1).
        if any(value.number == number for value in enum.values):
            return number, ""
        return None, f"{field.name} has no value numbered {number}; expected one of {', '.join(enum_names(field))}"
    bare = text.strip("'\"")
    if bare != text and bare in enum.values_by_name:
        return None, f'enum values are written without quotes: {field.name}: {bare}'
    hint = suggest(text, enum.values_by_name, upper=True)
    reason = f'unknown value "{text}" for {field.name} (enum {enum.name})'
    if hint:
        return None, f'{reason}; did you mean "{hint}"?'
    return None, f"{reason}; expected one of {', '.join(enum_names(field))}"


def _blocks() -> dict[str, str]:
    """Message full name -> the block name it is written as (`joshua.v1.Node` -> `node`)."""
    robot = RobotConfig.DESCRIPTOR
    blocks = {robot.full_name: "robot_config"}
    for name in ("node", "shutdown", "simulation"):
        blocks[robot.fields_by_name[name].message_type.full_name] = name
    return blocks


def _field_homes() -> dict[str, str]:
    """Every schema field name -> the block it belongs in, for "belongs in ..." hints."""
    homes: dict[str, str] = {}
    pool = RobotConfig.DESCRIPTOR.file.pool
    for full_name, block in _BLOCKS.items():
        for name in pool.FindMessageTypeByName(full_name).fields_by_name:
            homes.setdefault(name, block)
    return homes


_BLOCKS = _blocks()
_HOMES = _field_homes()


class _Binder:
    def __init__(self, path: str):
        self.path = path
        self.source = SourceMap(path)
        self.diagnostics: list[Diagnostic] = []

    def location(self, first: Token, last: Token) -> Location:
        return Location(self.path, first.line, first.column, last.line, last.end_column)

    def report(self, code: str, first: Token, last: Token, message: str, related: tuple[Related, ...] = ()):
        where = self.location(first, last)
        self.diagnostics.append(Diagnostic(self.path, where.line, where.column, code, ERROR, message,
                                           where.end_line, where.end_column, related))

    def related(self, token: Token, message: str) -> tuple[Related, ...]:
        return (Related(self.path, token.line, token.column, message),)

    def bind_fields(self, fields: list[Field], message, path: Path) -> None:
        seen: dict[str, Field] = {}
        for field in fields:
            self.bind_field(field, message, path, seen)

    def unknown_field(self, field: Field, descriptor: Descriptor) -> None:
        name = field.name.text
        message = f'unknown field "{name}" in {descriptor.name}'
        hint = suggest(name, descriptor.fields_by_name)
        if hint:
            message += f'; did you mean "{hint}"?'
        elif name in _HOMES and _HOMES[name] != _BLOCKS.get(descriptor.full_name):
            message += f"; it belongs in {_HOMES[name]} {{ ... }}"
        self.report(UNKNOWN_FIELD, field.name, field.name, message)

    def bind_field(self, field: Field, message, path: Path, seen: dict[str, Field]) -> None:
        descriptor = message.DESCRIPTOR
        name = field.name.text
        fd = descriptor.fields_by_name.get(name)
        if fd is None:
            self.unknown_field(field, descriptor)
            return
        key = path + (name,)
        if not fd.is_repeated:
            first = seen.get(name)
            if first is not None:
                self.report(DUPLICATE_FIELD, field.name, field.name,
                            f'field "{name}" is given twice in {descriptor.name}; it takes one value',
                            self.related(first.name, "first given here"))
                return
            seen[name] = field
        self.source.add(key, self.location(field.name, field.value.last))
        if fd.message_type is not None:
            self.bind_message_field(field, fd, message, key)
        else:
            self.bind_scalar_field(field, fd, message, key)

    def blocks_of(self, field: Field, fd: FieldDescriptor) -> list[Block]:
        value = field.value
        if isinstance(value, Block):
            return [value]
        if isinstance(value, Scalar):
            self.report(INVALID_VALUE, value.first, value.last,
                        f'"{fd.name}" is a message: write {fd.name} {{ ... }}')
            return []
        if not fd.is_repeated:
            self.report(INVALID_VALUE, value.open, value.open,
                        f'"{fd.name}" is not repeated: write {fd.name} {{ ... }}')
            return []
        blocks = []
        for item in value.items:
            if isinstance(item, Block):
                blocks.append(item)
            else:
                self.report(INVALID_VALUE, item.first, item.last,
                            f'"{fd.name}" holds messages: write {{ ... }}, not {_shown(item)}')
        return blocks

    def bind_message_field(self, field: Field, fd: FieldDescriptor, message, key: Path) -> None:
        listed = isinstance(field.value, ListValue)
        for block in self.blocks_of(field, fd):
            if fd.message_type.GetOptions().map_entry:
                self.bind_map_entry(block, fd, message, key)
            elif fd.is_repeated:
                container = getattr(message, fd.name)
                element = key + (len(container),)
                start = block.open if listed else field.name
                self.source.add(element, self.location(start, start))
                self.bind_fields(block.fields, container.add(), element)
            else:
                child = getattr(message, fd.name)
                child.SetInParent()
                self.bind_fields(block.fields, child, key)

    def bind_map_entry(self, block: Block, fd: FieldDescriptor, message, key: Path) -> None:
        container = getattr(message, fd.name)
        entry = container.GetEntryClass()()
        before = len(self.diagnostics)
        self.bind_fields(block.fields, entry, key + (len(container),))
        if len(self.diagnostics) != before:
            return
        key_field = next((f for f in block.fields if f.name.text == "key"), None)
        anchor = key_field.value.first if key_field else block.open
        entry_key = key + (entry.key,)
        previous = self.source.get(entry_key)
        if previous is not None:
            self.report(DUPLICATE_FIELD, anchor, anchor, f'{fd.name} key "{entry.key}" is given twice',
                        (Related(self.path, previous.line, previous.column, "first given here"),))
            return
        self.source.add(entry_key, self.location(anchor, anchor))
        container[entry.key] = entry.value

    def bind_scalar_field(self, field: Field, fd: FieldDescriptor, message, key: Path) -> None:
        value = field.value
        if isinstance(value, Block):
            self.report(INVALID_VALUE, value.open, value.open,
                        f'"{fd.name}" takes a value, not a message: write {fd.name}: ...')
            return
        if isinstance(value, ListValue):
            if not fd.is_repeated:
                self.report(INVALID_VALUE, value.open, value.open, f'"{fd.name}" takes one value, not a list')
                return
            if not field.colon:
                self.report(SYNTAX_ERROR, value.open, value.open, f'expected ":" after field name "{fd.name}"')
                return
            items = value.items
        else:
            items = [value]
        container = getattr(message, fd.name) if fd.is_repeated else None
        for item in items:
            if isinstance(item, Block):
                self.report(INVALID_VALUE, item.open, item.open,
                            f'"{fd.name}" takes values, not messages')
                continue
            parsed = self.scalar_value(fd, item)
            if parsed is None:
                continue
            if container is None:
                setattr(message, fd.name, parsed)
            else:
                self.source.add(key + (len(container),), self.location(item.first, item.last))
                container.append(parsed)

    def scalar_value(self, fd: FieldDescriptor, item: Scalar):
        if fd.type == FieldDescriptor.TYPE_ENUM:
            text = " ".join(t.text for t in item.tokens)
            number, reason = parse_enum(fd, text)
            if number is None:
                self.report(UNKNOWN_ENUM_VALUE, item.first, item.last, reason)
            return number
        try:
            return parse_scalar(fd, item)
        except ValueProblem as problem:
            self.report(INVALID_VALUE, item.first, item.last, str(problem))
            return None


def _wrong_root(binder: _Binder, fields: list[Field]) -> list[Field]:
    """Report config fields written at the file root once; keep the other root fields."""
    kept, reported = [], False
    robot_fields = RobotConfig.DESCRIPTOR.fields_by_name
    for field in fields:
        name = field.name.text
        if name not in RobotDescription.DESCRIPTOR.fields_by_name and name in robot_fields:
            if not reported:
                binder.report(MISSING_ROBOT_CONFIG, field.name, field.name,
                              f'"{name}" belongs inside robot_config {{ ... }}: '
                              "the file root holds one robot_config block")
                reported = True
            continue
        kept.append(field)
    return kept


def load_text(path: str, text: str) -> LoadResult:
    """Parse and bind one description; never raises for any input text."""
    binder = _Binder(path)
    try:
        document = parse_syntax(text)
    except SyntaxProblem as problem:
        binder.diagnostics.append(Diagnostic(path, problem.line, problem.column, SYNTAX_ERROR, ERROR,
                                             problem.message, problem.line, problem.end_column))
        return LoadResult(None, binder.source, binder.diagnostics)
    description = RobotDescription()
    binder.bind_fields(_wrong_root(binder, document.fields), description, ())
    if not document.fields:
        binder.diagnostics.append(Diagnostic(path, 1, 1, MISSING_ROBOT_CONFIG, ERROR,
                                             "the description is empty: expected robot_config { ... }"))
    elif not binder.diagnostics and not description.HasField("robot_config"):
        binder.diagnostics.append(Diagnostic(path, 1, 1, MISSING_ROBOT_CONFIG, ERROR,
                                             "missing robot_config { ... }"))
    if binder.diagnostics:
        return LoadResult(None, binder.source, binder.diagnostics)
    return LoadResult(description, binder.source, [])
