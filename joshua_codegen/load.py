"""Loader: .pbtxt text to a RobotDescription plus the source position of every field and value.

It binds the syntax tree of `syntax.py` to the schema and reports every unknown field, bad value
and repeated field at once (E002-E005); a syntax error (E001) ends parsing. What it accepts,
`google.protobuf.text_format.Parse` accepts too, with the same result; it is stricter in three ways:
a singular field may be written only once, enum numbers must name a value, and map keys are unique.
"""

from __future__ import annotations

from dataclasses import dataclass

from google.protobuf.descriptor import Descriptor, FieldDescriptor

from joshua_codegen.diagnostics import ERROR, Diagnostic, Related
from joshua_codegen.positions import Location, Path, SourceMap
from joshua_core.schema import RobotConfig, RobotDescription
from joshua_codegen.syntax import Block, Field, ListValue, Scalar, SyntaxProblem, Token, parse_syntax
from joshua_codegen.values import ValueProblem, parse_enum, parse_scalar, shown, suggest

SYNTAX_ERROR = "E001"
UNKNOWN_FIELD = "E002"
INVALID_VALUE = "E003"
UNKNOWN_ENUM_VALUE = "E004"
DUPLICATE_FIELD = "E005"
MISSING_ROBOT_CONFIG = "E006"
UNREADABLE_FILE = "E007"
NOT_TEXT = "E008"
NOT_REGULAR_FILE = "E009"

@dataclass
class LoadResult:
    description: RobotDescription | None  # None when any load error was found
    source_map: SourceMap
    diagnostics: list[Diagnostic]


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
                            f'"{fd.name}" holds messages: write {{ ... }}, not {shown(item)}')
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
