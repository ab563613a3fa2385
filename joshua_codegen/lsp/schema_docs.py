"""The comments of the schema's .proto file, by field and enum value: what hover shows.

The schema's meaning lives in the comments of `proto/joshua/v1/robot_config.proto` (the wheel ships it
as `_proto_src`). Each field and enum value takes the `//` lines right above it (or the comment after it
on its line); an enum value without one takes the comment of the run of values it belongs to, and
every message and enum its own comment.
"""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

SCHEMA_FILE = "joshua/v1/robot_config.proto"
PROTO_DIRS = (Path(__file__).resolve().parent.parent / "_proto_src", Path(__file__).resolve().parents[2] / "proto")

_COMMENT = re.compile(r"^\s*//\s?(.*)$")
_SCOPE = re.compile(r"^\s*(message|enum)\s+(\w+)\s*\{")
_FIELD = re.compile(r"^\s*(?:optional\s+|repeated\s+)?(?:map<[^>]*>|[\w.]+)\s+(\w+)\s*=\s*\d+[^;]*;\s*(?://\s?(.*))?$")
_ENUM_VALUE = re.compile(r"^\s*(\w+)\s*=\s*-?\d+[^;]*;\s*(?://\s?(.*))?$")


def schema_path() -> Path | None:
    for directory in PROTO_DIRS:
        path = directory / SCHEMA_FILE
        if path.is_file():
            return path
    return None


def parse_comments(text: str) -> dict[str, str]:
    """`Message.field`, `Enum.VALUE`, `Message` and `Enum` -> their comment, from .proto text."""
    docs: dict[str, str] = {}
    scopes: list[tuple[str, str]] = []  # (kind, name) of the open message and enum blocks
    pending: list[str] = []
    group = ""  # the comment of the run of enum values being read
    for line in text.splitlines():
        comment = _COMMENT.match(line)
        if comment:
            pending.append(comment.group(1).rstrip())
            continue
        scope = _SCOPE.match(line)
        if scope:
            scopes.append((scope.group(1), scope.group(2)))
            if pending:
                docs[scope.group(2)] = " ".join(pending)
            pending, group = [], ""
            continue
        if line.strip().startswith("}") and scopes:
            scopes.pop()
            pending, group = [], ""
            continue
        if not scopes:
            pending = []
            continue
        kind, name = scopes[-1]
        match = (_ENUM_VALUE if kind == "enum" else _FIELD).match(line)
        if match:
            own = " ".join(pending + ([match.group(2)] if match.group(2) else []))
            if kind == "enum":
                group = own or group
                own = group
            if own:
                docs[f"{name}.{match.group(1)}"] = own
        pending = [] if line.strip() else pending
    return docs


@cache
def schema_comments() -> dict[str, str]:
    """The comments of the installed schema (empty when its .proto file is not there)."""
    path = schema_path()
    return parse_comments(path.read_text(encoding="utf-8")) if path else {}
