"""Scalar values of the text format checked against a schema field: integers, floats, strings, enums.

Shared by the loader and the `--set` parser; every problem is a ValueProblem with a message for the user.
"""

from __future__ import annotations

import difflib
import re

from google.protobuf import text_encoding, text_format
from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen.syntax import Scalar

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
            escape = body[index : index + 2]
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


def shown(scalar: Scalar) -> str:
    text = " ".join(t.text for t in scalar.tokens)
    return text if len(text) <= 40 else text[:37] + "..."


def decode_string(scalar: Scalar, name: str = "the field") -> str:
    """A string literal's value; ValueProblem for a non-string token, a bad escape or invalid UTF-8."""
    if not scalar.is_string:
        raise ValueProblem(f"{name} takes a quoted string, got {shown(scalar)}")
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
            raise ValueProblem(f"{field.name} takes a quoted string, got {shown(scalar)}")
        return unquote(scalar)
    text = scalar.first.text
    if scalar.is_string:
        raise ValueProblem(f"{field.name} takes {_kind_name(field)}, not a string; remove the quotes")
    if kind in _INTEGER_RANGES:
        described, low, high = _INTEGER_RANGES[kind]
        try:
            value = _parse_integer(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes {described}, got {shown(scalar)}") from None
        if not low <= value <= high:
            raise ValueProblem(f"{field.name} takes {described} ({low} to {high}), got {shown(scalar)}")
        return value
    if kind in _FLOATS:
        try:
            return text_format.ParseFloat(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes a number, got {shown(scalar)}") from None
    if kind == FieldDescriptor.TYPE_BOOL:
        try:
            return text_format.ParseBool(text)
        except ValueError:
            raise ValueProblem(f"{field.name} takes true or false, got {shown(scalar)}") from None
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
        return None, f"enum values are written without quotes: {field.name}: {bare}"
    hint = suggest(text, enum.values_by_name, upper=True)
    reason = f'unknown value "{text}" for {field.name} (enum {enum.name})'
    if hint:
        return None, f'{reason}; did you mean "{hint}"?'
    return None, f"{reason}; expected one of {', '.join(enum_names(field))}"
