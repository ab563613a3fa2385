"""The node-settings contract (proto/joshua/v1/node_settings.proto): its version, and the literal form a
generated entrypoint holds.

joshuac builds a NodeSettings message per process and writes `to_literal(settings)` into the
entrypoint; the runtime turns that literal back into the message with `parse`. Both sides therefore
agree on every field's name and type, and a build and a runtime of different contract versions
refuse each other in one line instead of misreading a field.
"""

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
    from google.protobuf import json_format  # imported on use: a check never needs it

    return json_format.MessageToDict(settings, preserving_proto_field_name=True)


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
