"""Hover: a field's schema comment, an enum value's meaning, and the explanation of the diagnostics there."""

from __future__ import annotations

from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen.diagnostics import Diagnostic
from joshua_codegen.lsp.cursor import NAME, cursor_at, word_at
from joshua_codegen.lsp.schema_docs import schema_comments
from joshua_codegen.rules import explain


def field_type(fd: FieldDescriptor) -> str:
    """`repeated string`, `Node`, `Reliability` ..., as the schema writes it."""
    if fd.message_type is not None:
        name = fd.message_type.name
    elif fd.enum_type is not None:
        name = fd.enum_type.name
    else:
        name = {
            FieldDescriptor.TYPE_STRING: "string",
            FieldDescriptor.TYPE_BOOL: "bool",
            FieldDescriptor.TYPE_DOUBLE: "double",
            FieldDescriptor.TYPE_FLOAT: "float",
            FieldDescriptor.TYPE_BYTES: "bytes",
        }.get(fd.type, "integer")
    return f"repeated {name}" if fd.is_repeated else name


def field_doc(fd: FieldDescriptor) -> str:
    """The schema comment of a field, or of its message or enum type when it has none."""
    comments = schema_comments()
    owner = fd.containing_type.name
    own = comments.get(f"{owner}.{fd.name}")
    kind = fd.message_type or fd.enum_type
    return own or (comments.get(kind.name, "") if kind is not None else "")


def enum_value_doc(fd: FieldDescriptor, value: str) -> str | None:
    """The meaning of an enum value: its own comment, else its enum's; None when the enum has no such value."""
    enum = fd.enum_type
    if enum is None or value not in enum.values_by_name:
        return None
    comments = schema_comments()
    return comments.get(f"{enum.name}.{value}") or comments.get(enum.name, "")


def _schema_part(text: str, line: int, column: int) -> str | None:
    word = word_at(text, line, column)
    if word is None:
        return None
    cursor = cursor_at(text, word.line, word.column)
    if cursor.expects == NAME:
        fd = cursor.message.fields_by_name.get(word.text) if cursor.message is not None else None
        if fd is None:
            return None
        return f"**{fd.name}**: `{field_type(fd)}`\n\n{field_doc(fd)}".rstrip()
    if cursor.field is not None and cursor.field.enum_type is not None:
        doc = enum_value_doc(cursor.field, word.text)
        if doc is None:
            return None
        return f"**{word.text}** ({cursor.field.enum_type.name})\n\n{doc}".rstrip()
    return None


def _covers(d: Diagnostic, line: int, column: int) -> bool:
    end_line = d.end_line if d.end_line is not None else d.line
    end_column = d.end_column if d.end_column is not None else d.column + 1
    return (d.line, d.column) <= (line, column) < (end_line, max(end_column, d.column + 1))


def hover_text(text: str, diagnostics: list[Diagnostic], line: int, column: int) -> str | None:
    """Markdown for the 1-based position, or None when there is nothing to say."""
    parts = []
    schema = _schema_part(text, line, column)
    if schema:
        parts.append(schema)
    for code in dict.fromkeys(d.code for d in diagnostics if _covers(d, line, column)):
        explanation = explain(code)
        if explanation:
            parts.append(f"**{code}**\n\n```text\n{explanation.rstrip()}\n```")
    return "\n\n---\n\n".join(parts) or None
