"""ROS messages to and from YAML text, in the form `ros2 topic echo` prints and `ros2 topic pub` reads."""

from __future__ import annotations

import array

import numpy
import yaml

from joshua_runtime.errors import SettingsError

# Arrays longer than this are printed as "'<sequence type: T, length: N>'", as ros2 topic echo does.
ECHO_ARRAY_LIMIT = 128


def to_plain(message, array_limit: int | None = ECHO_ARRAY_LIMIT):
    """A message as nested dicts, lists and scalars (field order kept)."""
    if hasattr(message, "get_fields_and_field_types"):
        return {field: to_plain(getattr(message, field), array_limit) for field in message.get_fields_and_field_types()}
    if isinstance(message, (list, tuple, array.array, numpy.ndarray)):
        if array_limit is not None and len(message) > array_limit:
            return f"<sequence, length: {len(message)}>"
        return [to_plain(item, array_limit) for item in message]
    if isinstance(message, bytes):
        return list(message)
    if isinstance(message, numpy.generic):
        return message.item()
    return message


def to_yaml(message, array_limit: int | None = ECHO_ARRAY_LIMIT) -> str:
    """YAML text of a message, fields in definition order, ending with the `---` separator."""
    return (
        yaml.safe_dump(to_plain(message, array_limit), sort_keys=False, default_flow_style=False, allow_unicode=True)
        + "---\n"
    )


def from_yaml(message_class, text: str):
    """A message of `message_class` with the fields the YAML mapping `text` gives; the rest default.

    Raises SettingsError with one line naming the bad field.
    """
    try:
        values = yaml.safe_load(text) if text.strip() else {}
    except yaml.YAMLError as exc:
        raise SettingsError(f"the values are not YAML: {str(exc).splitlines()[0]}") from exc
    message = message_class()
    fill(message, values or {}, message_class.__name__)
    return message


def fill(message, values, path: str) -> None:
    """Set the fields of `message` from the mapping `values` (nested mappings fill nested messages)."""
    if not isinstance(values, dict):
        raise SettingsError(f"{path}: expected a mapping of field names to values, got {values!r}")
    fields = message.get_fields_and_field_types()
    for name, value in values.items():
        where = f"{path}.{name}"
        if name not in fields:
            raise SettingsError(f"{where}: no such field (fields: {', '.join(fields)})")
        current = getattr(message, name)
        try:
            if hasattr(current, "get_fields_and_field_types"):
                fill(current, value, where)
            elif isinstance(value, list) and value and isinstance(value[0], dict):
                item_class = _sequence_item_class(message, name)
                items = []
                for index, item_values in enumerate(value):
                    item = item_class()
                    fill(item, item_values, f"{where}[{index}]")
                    items.append(item)
                setattr(message, name, items)
            else:
                setattr(message, name, value)
        except (TypeError, ValueError, AssertionError) as exc:
            raise SettingsError(f"{where}: cannot take {value!r} ({fields[name]})") from exc


def _sequence_item_class(message, field: str):
    """The message class of the items of a sequence field, from the generated slot types."""
    slot_type = message.SLOT_TYPES[list(message.get_fields_and_field_types()).index(field)]
    item = getattr(slot_type, "value_type", None)
    namespaces = getattr(item, "namespaces", None)
    if not namespaces:
        raise TypeError(f"{field} does not hold messages")
    module = __import__(".".join(namespaces), fromlist=[item.name])
    return getattr(module, item.name)
