"""Completion at a cursor: the field names of the message there, enum values, and names used elsewhere."""

from __future__ import annotations

from dataclasses import dataclass

from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen.lsp.cursor import NAME, Cursor
from joshua_codegen.lsp.hover import field_doc, field_type
from joshua_codegen.lsp.schema_docs import schema_comments

# Fields whose value names a topic, by the schema's naming: topic_name, state_topic, odom_topic, input_topics.
TOPIC_FIELD_SUFFIXES = ("topic", "topics", "topic_name")
# Fields whose value names a node of the description.
NODE_FIELD_SUFFIXES = ("_node", "_nodes")
FIELD, ENUM_VALUE, VALUE = "field", "enum value", "value"


@dataclass(frozen=True)
class Suggestion:
    label: str
    kind: str  # FIELD, ENUM_VALUE or VALUE
    detail: str
    documentation: str
    insert: str  # the text that replaces the word at the cursor


def _quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _names(fd: FieldDescriptor, topics: list[str], nodes: list[str]) -> list[str]:
    if fd.type != FieldDescriptor.TYPE_STRING:
        return []
    if fd.name.endswith(TOPIC_FIELD_SUFFIXES):
        return topics
    if fd.name.endswith(NODE_FIELD_SUFFIXES):
        return nodes
    return []


def suggestions(cursor: Cursor, topics: list[str], nodes: list[str]) -> list[Suggestion]:
    """What may be written at the cursor, filtered by the word typed so far."""
    found: list[Suggestion] = []
    if cursor.expects == NAME:
        if cursor.message is None:
            return []
        for fd in cursor.message.fields:
            found.append(Suggestion(fd.name, FIELD, field_type(fd), field_doc(fd), fd.name))
    elif cursor.field is not None and cursor.field.enum_type is not None:
        comments = schema_comments()
        enum = cursor.field.enum_type
        for value in enum.values:
            if value.number == 0:  # X_UNSPECIFIED: never a choice
                continue
            doc = comments.get(f"{enum.name}.{value.name}") or comments.get(enum.name, "")
            found.append(Suggestion(value.name, ENUM_VALUE, enum.name, doc, value.name))
    elif cursor.field is not None and cursor.field.type == FieldDescriptor.TYPE_BOOL:
        found += [Suggestion(v, VALUE, "bool", "", v) for v in ("true", "false")]
    elif cursor.field is not None:
        what = "topic" if cursor.field.name.endswith(TOPIC_FIELD_SUFFIXES) else "node"
        for name in _names(cursor.field, topics, nodes):
            found.append(Suggestion(name, VALUE, f"{what} used in this description", "", _quoted(name)))
    typed = cursor.prefix.lstrip("\"'")
    return [s for s in found if s.label.startswith(typed)]
