"""Loader: .pbtxt text to a RobotDescription plus the source position of every field and value.

It binds the syntax tree of `syntax.py` to the schema and reports every unknown field, bad value
and repeated field at once (E002-E005), and every syntax error (E001) it can get past
(`syntax_recovery.py`). A node holding any of these problems is "unknown": the partial description
keeps it, empty or half-read, and names it in `unknown_nodes`, so the rules can check the rest. What it accepts,
`google.protobuf.text_format.Parse` accepts too, with the same result; it is stricter in three ways:
a singular field may be written only once, enum numbers must name a value, and map keys are unique.
"""

from __future__ import annotations

from dataclasses import dataclass

from google.protobuf.descriptor import Descriptor, FieldDescriptor

from joshua_codegen.diagnostics import ERROR, Diagnostic, Related
from joshua_codegen.positions import Location, Path, SourceMap
from joshua_codegen.syntax import Block, Broken, Field, ListValue, Scalar, SyntaxProblem, Token
from joshua_codegen.syntax_recovery import parse_recovering
from joshua_codegen.values import ValueProblem, parse_enum, parse_scalar, shown, suggest
from joshua_core.schema import RobotConfig, RobotDescription

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
    # What could be read despite the errors: every node but those in `unknown_nodes` is as written.
    # None when a problem lies outside the nodes (robot settings, the file root): nothing is known then.
    partial: RobotDescription | None = None
    unknown_nodes: frozenset[int] = frozenset()


def _blocks() -> dict[str, str]:
    """Message full name -> the block name it is written as (`joshua.v1.Node` -> `node`)."""
    robot = RobotConfig.DESCRIPTOR
    blocks = {robot.full_name: "robot_config"}
    for name in ("node", "shutdown", "simulation", "foxglove"):
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
_ROBOT_FILE = RobotConfig.DESCRIPTOR.file  # "belongs in" hints are for descriptions, not fleet files


class _Binder:
    def __init__(self, path: str):
        self.path = path
        self.source = SourceMap(path)
        self.diagnostics: list[Diagnostic] = []
        self.node_index: int | None = None  # the node being bound, if any
        self.unknown_nodes: set[int] = set()
        self.outside_nodes = False  # a problem was found outside every node

    def location(self, first: Token, last: Token) -> Location:
        return Location(self.path, first.line, first.column, last.line, last.end_column)

    def report(self, code: str, first: Token, last: Token, message: str, related: tuple[Related, ...] = ()):
        if self.node_index is None:
            self.outside_nodes = True
        else:
            self.unknown_nodes.add(self.node_index)
        where = self.location(first, last)
        self.diagnostics.append(
            Diagnostic(
                self.path, where.line, where.column, code, ERROR, message, where.end_line, where.end_column, related
            )
        )

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
        elif descriptor.file is _ROBOT_FILE and name in _HOMES and _HOMES[name] != _BLOCKS.get(descriptor.full_name):
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
                self.report(
                    DUPLICATE_FIELD,
                    field.name,
                    field.name,
                    f'field "{name}" is given twice in {descriptor.name}; it takes one value',
                    self.related(first.name, "first given here"),
                )
                return
            seen[name] = field
        self.source.add(key, self.location(field.name, field.value.last))
        if fd.message_type is not None:
            self.bind_message_field(field, fd, message, key)
        else:
            self.bind_scalar_field(field, fd, message, key)

    def blocks_of(self, field: Field, fd: FieldDescriptor) -> list[Block]:
        value = field.value
        if isinstance(value, (Block, Broken)):
            return [value]
        if isinstance(value, Scalar):
            self.report(INVALID_VALUE, value.first, value.last, f'"{fd.name}" is a message: write {fd.name} {{ ... }}')
            return []
        if not fd.is_repeated:
            self.report(
                INVALID_VALUE, value.open, value.open, f'"{fd.name}" is not repeated: write {fd.name} {{ ... }}'
            )
            return []
        blocks = []
        for item in value.items:
            if isinstance(item, Block):
                blocks.append(item)
            else:
                self.report(
                    INVALID_VALUE,
                    item.first,
                    item.last,
                    f'"{fd.name}" holds messages: write {{ ... }}, not {shown(item)}',
                )
        return blocks

    def bind_message_field(self, field: Field, fd: FieldDescriptor, message, key: Path) -> None:
        listed = isinstance(field.value, ListValue)
        for block in self.blocks_of(field, fd):
            if isinstance(block, Broken) and not fd.is_repeated:
                self.report_known_problem()
            elif fd.message_type.GetOptions().map_entry:
                self.bind_map_entry(block, fd, message, key)
            elif fd.is_repeated:
                container = getattr(message, fd.name)
                element = key + (len(container),)
                start = block.first if listed else field.name
                self.source.add(element, self.location(start, start))
                self.bind_element(block, container.add(), element)
            else:
                child = getattr(message, fd.name)
                child.SetInParent()
                self.bind_fields(block.fields, child, key)

    def bind_element(self, block: Block | Broken, element, path: Path) -> None:
        """One element of a repeated message field; a node's problems make that node unknown."""
        is_node = path[:2] == ("robot_config", "node")
        outer = self.node_index
        if is_node:
            self.node_index = path[2]
        if isinstance(block, Broken):  # its syntax error is reported already
            self.report_known_problem()
        else:
            self.bind_fields(block.fields, element, path)
        self.node_index = outer

    def bind_map_entry(self, block: Block | Broken, fd: FieldDescriptor, message, key: Path) -> None:
        container = getattr(message, fd.name)
        entry = container.GetEntryClass()()
        if isinstance(block, Broken):
            self.report_known_problem()
            return
        before = len(self.diagnostics)
        self.bind_fields(block.fields, entry, key + (len(container),))
        if len(self.diagnostics) != before:
            return
        key_field = next((f for f in block.fields if f.name.text == "key"), None)
        anchor = key_field.value.first if key_field else block.open
        entry_key = key + (entry.key,)
        previous = self.source.get(entry_key)
        if previous is not None:
            self.report(
                DUPLICATE_FIELD,
                anchor,
                anchor,
                f'{fd.name} key "{entry.key}" is given twice',
                (Related(self.path, previous.line, previous.column, "first given here"),),
            )
            return
        self.source.add(entry_key, self.location(anchor, anchor))
        container[entry.key] = entry.value

    def bind_scalar_field(self, field: Field, fd: FieldDescriptor, message, key: Path) -> None:
        value = field.value
        if isinstance(value, Broken):  # its syntax error is reported already
            self.report_known_problem()
            return
        if isinstance(value, Block):
            self.report(
                INVALID_VALUE, value.open, value.open, f'"{fd.name}" takes a value, not a message: write {fd.name}: ...'
            )
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
                self.report(INVALID_VALUE, item.open, item.open, f'"{fd.name}" takes values, not messages')
                continue
            parsed = self.scalar_value(fd, item)
            if parsed is None:
                continue
            if container is None:
                setattr(message, fd.name, parsed)
            else:
                self.source.add(key + (len(container),), self.location(item.first, item.last))
                container.append(parsed)

    def report_known_problem(self) -> None:
        """Mark the current scope as not understood, for a problem reported elsewhere."""
        if self.node_index is None:
            self.outside_nodes = True
        else:
            self.unknown_nodes.add(self.node_index)

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
                binder.report(
                    MISSING_ROBOT_CONFIG,
                    field.name,
                    field.name,
                    f'"{name}" belongs inside robot_config {{ ... }}: the file root holds one robot_config block',
                )
                reported = True
            continue
        kept.append(field)
    return kept


def syntax_diagnostic(path: str, problem: SyntaxProblem) -> Diagnostic:
    """The E001 diagnostic of a syntax problem, with its notes."""
    related = tuple(Related(path, line, column, message) for line, column, message in problem.notes)
    return Diagnostic(
        path,
        problem.line,
        problem.column,
        SYNTAX_ERROR,
        ERROR,
        problem.message,
        problem.line,
        problem.end_column,
        related,
    )


def load_text(path: str, text: str) -> LoadResult:
    """Parse and bind one description; never raises for any input text."""
    binder = _Binder(path)
    document, problems = parse_recovering(text)
    binder.diagnostics += [syntax_diagnostic(path, problem) for problem in problems]
    if document is None:
        return LoadResult(None, binder.source, binder.diagnostics)
    description = RobotDescription()
    binder.bind_fields(_wrong_root(binder, document.fields), description, ())
    if not document.fields:
        binder.diagnostics.append(
            Diagnostic(
                path, 1, 1, MISSING_ROBOT_CONFIG, ERROR, "the description is empty: expected robot_config { ... }"
            )
        )
    elif not binder.diagnostics and not description.HasField("robot_config"):
        binder.diagnostics.append(Diagnostic(path, 1, 1, MISSING_ROBOT_CONFIG, ERROR, "missing robot_config { ... }"))
    if binder.diagnostics:
        understood = not binder.outside_nodes and description.HasField("robot_config")
        return LoadResult(
            None,
            binder.source,
            binder.diagnostics,
            description if understood else None,
            frozenset(binder.unknown_nodes),
        )
    return LoadResult(description, binder.source, [])


def load_message(path: str, text: str, root_type):
    """Parse and bind a text whose file root is another schema message (`root_type`, e.g. a fleet's):
    (the message, or None when any problem was found; source positions; every load diagnostic)."""
    binder = _Binder(path)
    document, problems = parse_recovering(text)
    binder.diagnostics += [syntax_diagnostic(path, problem) for problem in problems]
    if document is None:
        return None, binder.source, binder.diagnostics
    message = root_type()
    binder.bind_fields(document.fields, message, ())
    return (None if binder.diagnostics else message), binder.source, binder.diagnostics
