"""`joshuac fmt`: the canonical text of a description, keeping every comment.

Canonical form: 2-space indentation; `field: value` for values and `field {` for messages
(`<...>` becomes `{...}`, separators `,`/`;` are dropped); repeated values as `[a, b, c]` on one
line; a list of messages as one `field {` block per element; strings double-quoted with canonical
escapes (adjacent strings joined); fields in the order written; one blank line between the nodes
of robot_config, at most one blank line kept elsewhere and none at the start or end of a block.
Comments stay on their line (`value  # comment`) or above the field they precede; comments inside
a value list move above its field. Formatting is idempotent and never changes what the file means.
It needs only valid syntax and valid string escapes (unknown fields are formatted as written).

The text starts with the header of the text-format specification, `# proto-file: ...` and
`# proto-message: ...`, which tells editors and other tools the schema of the file; other comments
at the top follow it, and header lines naming another schema are replaced.
"""

from __future__ import annotations

from joshua_codegen.check import decode
from joshua_codegen.diagnostics import ERROR, Diagnostic
from joshua_codegen.load import INVALID_VALUE, NOT_TEXT, load_text, syntax_diagnostic
from joshua_codegen.source_file import SourceProblem, read_description
from joshua_codegen.syntax import Block, Comment, Document, Field, ListValue, Scalar, SyntaxProblem, parse_syntax
from joshua_codegen.values import ValueProblem, unquote
from joshua_core.schema import FleetDescription, RobotDescription

INDENT = "  "
TRAILING_COMMENT_GAP = "  "
ROBOT_BLOCK = "robot_config"
NODE_FIELD = "node"
_ESCAPES = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\r": "\\r", "\t": "\\t"}
HEADER_KEYS = ("# proto-file:", "# proto-message:")
HEADER = (f"{HEADER_KEYS[0]} joshua/v1/robot_config.proto", f"{HEADER_KEYS[1]} {RobotDescription.DESCRIPTOR.full_name}")
FLEET_BLOCK = "fleet_config"  # a fleet file's root (fleet/load.py)
FLEET_HEADER = (
    f"{HEADER_KEYS[0]} joshua/v1/fleet_config.proto",
    f"{HEADER_KEYS[1]} {FleetDescription.DESCRIPTOR.full_name}",
)


def quote(data: bytes) -> str:
    """Canonical double-quoted literal for a string's bytes (UTF-8 kept readable, the rest escaped)."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return '"' + "".join(_byte(b) for b in data) + '"'
    out = []
    for char in text:
        if char in _ESCAPES:
            out.append(_ESCAPES[char])
        elif char.isascii():
            out.append(char if char.isprintable() else f"\\{ord(char):03o}")
        elif char.isprintable():
            out.append(char)
        else:
            out.append("".join(f"\\{b:03o}" for b in char.encode("utf-8")))
    return '"' + "".join(out) + '"'


def _byte(value: int) -> str:
    char = chr(value)
    if char in _ESCAPES:
        return _ESCAPES[char]
    if 0x20 <= value < 0x7F:
        return char
    return f"\\{value:03o}"


class _Printer:
    def __init__(self):
        self.lines: list[str] = []

    def blank(self) -> None:
        if self.lines and self.lines[-1] != "":
            self.lines.append("")

    def comments(self, comments: list[Comment], indent: str, next_line: int | None) -> None:
        for index, comment in enumerate(comments):
            if index and comment.line - comments[index - 1].line > 1:
                self.blank()
            self.lines.append(indent + comment.text)
        if comments and next_line is not None and next_line - comments[-1].line > 1:
            self.blank()

    def fields(self, fields: list[Field], indent: str, in_robot: bool) -> None:
        previous_was_node = False
        for index, field in enumerate(fields):
            is_node = in_robot and field.name.text == NODE_FIELD and not isinstance(field.value, Scalar)
            if index and (field.blank_before or is_node or previous_was_node):
                self.blank()
            self.field(field, indent, separate=is_node)
            previous_was_node = is_node

    def field(self, field: Field, indent: str, separate: bool = False) -> None:
        """Print one field; `separate` puts blank lines between the blocks of an expanded list."""
        name = field.name.text
        value = field.value
        leading = list(field.leading)
        if isinstance(value, ListValue):
            leading += value.inner_comments
        self.comments(leading, indent, field.name.line)
        trailing = f"{TRAILING_COMMENT_GAP}{field.trailing.text}" if field.trailing else ""
        if isinstance(value, Scalar):
            self.lines.append(f"{indent}{name}: {render_scalar(value)}{trailing}")
        elif isinstance(value, Block):
            self.block(name, value, indent, trailing, robot=name == ROBOT_BLOCK and not indent)
        elif all(isinstance(item, Scalar) for item in value.items):
            items = ", ".join(render_scalar(item) for item in value.items)
            self.lines.append(f"{indent}{name}: [{items}]{trailing}")
        else:
            for position, item in enumerate(value.items):
                if position and separate:
                    self.blank()
                last = position == len(value.items) - 1
                suffix = trailing if last else ""
                if isinstance(item, Block):
                    self.block(name, item, indent, suffix, robot=False)
                else:
                    self.lines.append(f"{indent}{name}: {render_scalar(item)}{suffix}")

    def block(self, name: str, block: Block, indent: str, trailing: str, robot: bool) -> None:
        opening = f"  {block.trailing_open.text}" if block.trailing_open else ""
        if not block.fields and not block.dangling and not opening:
            self.lines.append(f"{indent}{name} {{}}{trailing}")
            return
        self.lines.append(f"{indent}{name} {{{opening}")
        inner = indent + INDENT
        self.fields(block.fields, inner, in_robot=robot)
        if block.dangling:
            last = _last_line(block.fields[-1]) if block.fields else None
            if last is not None and block.dangling[0].line - last > 1:
                self.blank()
            self.comments(block.dangling, inner, None)
        self.lines.append(f"{indent}}}{trailing}")


def _last_line(field: Field) -> int:
    return field.trailing.line if field.trailing else field.value.last.line


def render_scalar(scalar: Scalar) -> str:
    if scalar.is_string:
        return quote(unquote(scalar))
    return scalar.first.text


def render(document: Document) -> str:
    """Canonical text of a parsed document (string escapes must already be valid)."""
    printer = _Printer()
    printer.fields(document.fields, "", in_robot=False)
    if document.dangling:
        last = _last_line(document.fields[-1]) if document.fields else None
        if last is not None and document.dangling[0].line - last > 1:
            printer.blank()
        printer.comments(document.dangling, "", None)
    fleet = bool(document.fields) and document.fields[0].name.text == FLEET_BLOCK
    return "".join(line + "\n" for line in _with_header(printer.lines, FLEET_HEADER if fleet else HEADER))


def _with_header(lines: list[str], header: tuple[str, str]) -> list[str]:
    """The lines with the schema header first, in place of any header lines among the comments at the top."""
    top = 0
    while top < len(lines) and lines[top].startswith("#"):
        top += 1
    kept = [line for line in lines[:top] if not line.startswith(HEADER_KEYS)]
    return [*header, *kept, *lines[top:]]


def _check_strings(fields: list[Field], path: str, problems: list[Diagnostic]) -> None:
    for field in fields:
        values = field.value.items if isinstance(field.value, ListValue) else [field.value]
        for value in values:
            if isinstance(value, Block):
                _check_strings(value.fields, path, problems)
            elif value.is_string:
                try:
                    unquote(value)
                except ValueProblem as problem:
                    problems.append(
                        Diagnostic(
                            path,
                            value.first.line,
                            value.first.column,
                            INVALID_VALUE,
                            ERROR,
                            str(problem),
                            value.last.line,
                            value.last.end_column,
                        )
                    )


def format_description(text: str, path: str) -> tuple[str | None, list[Diagnostic]]:
    """Canonical text of a description, or None and the diagnostics that prevent formatting it."""
    if text.startswith("\ufeff"):
        text = text[1:]
    if "\0" in text:
        before = text[: text.index("\0")]
        line = before.count("\n") + 1
        column = len(before) - (before.rfind("\n") + 1) + 1
        return None, [Diagnostic(path, line, column, NOT_TEXT, ERROR, "the file contains a NUL character")]
    try:
        document = parse_syntax(text)
    except SyntaxProblem as problem:
        return None, [syntax_diagnostic(path, problem)]
    problems: list[Diagnostic] = []
    _check_strings(document.fields, path, problems)
    if problems:
        return None, problems
    return render(document), []


class MeaningChanged(AssertionError):
    """The canonical text would load differently from the original: a formatter bug, never written."""


def format_file(path: str) -> tuple[str, str | None, list[Diagnostic]]:
    """(text, canonical text or None, diagnostics) of a description file.

    None when the file cannot be read, is not UTF-8 text, or cannot be parsed: such a file is
    never rewritten. The canonical text is proven to load to the same description as the original.
    """
    try:
        data = read_description(path)
    except SourceProblem as problem:
        return "", None, [problem.diagnostic]
    text, problems = decode(path, data)
    if text is None:
        return data.decode("utf-8", errors="replace"), None, problems
    formatted, problems = format_description(text, path)
    if formatted is not None and _meaning(path, text.removeprefix("\ufeff")) != _meaning(path, formatted):
        raise MeaningChanged(f"formatting {path} would change what it means; the file is left as it is")
    return text, formatted, problems


def _meaning(path: str, text: str):
    """What a text loads to, as a description or, for a fleet file, as a fleet."""
    from joshua_codegen.fleet.load import is_fleet_text, load_fleet

    return load_fleet(path, text)[0] if is_fleet_text(text) else load_text(path, text).description
