"""The node-settings contract (proto/joshua/v1/node_settings.proto): its version, and the literal form a
generated entrypoint holds.

joshuac builds a NodeSettings message per process and writes `to_literal(settings)` into the
entrypoint; the runtime turns that literal back into the message with `parse`. Both sides therefore
agree on every field's name and type, and a build and a runtime of different contract versions
refuse each other in one line instead of misreading a field.
"""

import math
from functools import cache

from google.protobuf.descriptor import Descriptor, FieldDescriptor

from joshua_core.schema.node_settings_pb2 import (
    NodeSettings,
    PresetSettings,
    QosSettings,
    SimulationSettings,
    TopicSettings,
)

# Raise on every change of node_settings.proto that an older runtime or an older build could misread.
FORMAT_VERSION = 5

__all__ = [
    "FORMAT_VERSION",
    "NodeSettings",
    "PresetSettings",
    "QosSettings",
    "SettingsFormatError",
    "SimulationSettings",
    "TopicSettings",
    "parse",
    "to_literal",
]


class SettingsFormatError(ValueError):
    """Settings that are not of this contract: another version, an unknown field, a wrong type."""


def to_literal(settings: NodeSettings) -> dict:
    """The JSON form of the settings as plain Python values (what an entrypoint's SETTINGS holds).

    Fields at their zero value ("" / 0 / false / empty / unset) are left out, fields in field-number
    order: an entrypoint shows what is set for its node and nothing else.
    """
    if not _plain(settings.DESCRIPTOR):
        from google.protobuf import json_format  # imported on use: a check never needs it

        return json_format.MessageToDict(settings, preserving_proto_field_name=True)
    return _literal(settings)


# Field types whose JSON form is the Python value itself (a double only when finite): for messages made of
# these, `_literal` writes what json_format.MessageToDict does at a fifth of its cost (a build of a
# thousand nodes converts a thousand settings).
_PLAIN_TYPES = {
    FieldDescriptor.TYPE_STRING,
    FieldDescriptor.TYPE_BOOL,
    FieldDescriptor.TYPE_UINT32,
    FieldDescriptor.TYPE_DOUBLE,
}
_NOT_FINITE = {math.inf: "Infinity", -math.inf: "-Infinity"}


@cache
def _plain(message: Descriptor) -> bool:
    """Whether a message type and every one it nests (NodeSettings nests itself) have only fields of the
    plain types: no enum, 64-bit integer, bytes, float or well-known type, which json_format writes its way."""
    pending, seen = [message], set()
    while pending:
        current = pending.pop()
        if current.full_name in seen:
            continue
        seen.add(current.full_name)
        if current.full_name.startswith("google.protobuf."):
            return False
        for field in current.fields:
            if field.type == FieldDescriptor.TYPE_MESSAGE:
                pending.append(field.message_type)
            elif field.type not in _PLAIN_TYPES:
                return False
    return True


def _literal(message) -> dict:
    literal = {}
    for field, value in message.ListFields():
        if field.type != FieldDescriptor.TYPE_MESSAGE:
            literal[field.name] = [_value(field, item) for item in value] if field.is_repeated else _value(field, value)
        elif field.message_type.GetOptions().map_entry:
            entry = field.message_type.fields_by_name["value"]
            literal[field.name] = {
                ("true" if key else "false") if isinstance(key, bool) else str(key): _value(entry, value[key])
                for key in value
            }
        elif field.is_repeated:
            literal[field.name] = [_literal(item) for item in value]
        else:
            literal[field.name] = _literal(value)
    return literal


def _value(field, value):
    if field.type == FieldDescriptor.TYPE_MESSAGE:
        return _literal(value)
    if field.type == FieldDescriptor.TYPE_DOUBLE and not math.isfinite(value):
        return "NaN" if math.isnan(value) else _NOT_FINITE[value]
    return value


def parse(literal: dict) -> NodeSettings:
    """The message of an entrypoint's SETTINGS; SettingsFormatError names what does not fit."""
    if not isinstance(literal, dict):
        raise SettingsFormatError(f"settings must be a dict, got {type(literal).__name__}")
    version = literal.get("format_version")
    if version != FORMAT_VERSION:
        raise SettingsFormatError(
            f"settings are of format version {version}, this joshua_runtime reads version {FORMAT_VERSION}; "
            "rebuild with the joshuac that matches the installed runtime"
        )
    from google.protobuf import json_format

    try:
        return json_format.ParseDict(literal, NodeSettings())
    except json_format.ParseError as exc:
        reason = str(exc).splitlines()[0]  # protobuf lists every known field on the lines after
        raise SettingsFormatError(f"settings do not fit format version {FORMAT_VERSION}: {reason}") from None
