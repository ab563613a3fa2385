"""Full ROS 2 message definitions (`ros2msg`), as rosbag2 stores them in an MCAP schema.

A definition is the type's .msg text followed by the .msg text of every type it refers to, each
after a line of 80 `=` and `MSG: pkg/Type`. The .msg files come from `share/<pkg>/msg/` of the
environment (where the ROS wheels and set-up's interface build install them) or of AMENT_PREFIX_PATH.
"""

from __future__ import annotations

import functools
import os
import pathlib
import re
import sys

from joshua_runtime.errors import SettingsError

SEPARATOR = "=" * 80
PRIMITIVES = frozenset(
    {
        "bool",
        "byte",
        "char",
        "float32",
        "float64",
        "int8",
        "uint8",
        "int16",
        "uint16",
        "int32",
        "uint32",
        "int64",
        "uint64",
        "string",
        "wstring",
    }
)
_FIELD_TYPE = re.compile(r"^\s*([A-Za-z][\w/]*)")


def full_definition(message_type: str) -> str:
    """The concatenated definition of `pkg/msg/Type`; SettingsError when a .msg file is missing."""
    package, name = _split(message_type)
    main = _msg_text(package, name)
    order: list[tuple[str, str]] = []

    def visit(owner: str, text: str) -> None:
        for dependency in _referenced_types(owner, text):
            if dependency not in order:
                order.append(dependency)
                visit(dependency[0], _msg_text(*dependency))

    visit(package, main)
    return main + "".join(f"\n{SEPARATOR}\nMSG: {pkg}/{typ}\n{_msg_text(pkg, typ)}" for pkg, typ in order)


def _split(message_type: str) -> tuple[str, str]:
    parts = message_type.split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return parts[0], parts[2]
    if len(parts) == 2:
        return parts[0], parts[1]
    raise SettingsError(f"{message_type!r} is not a message type of the form pkg/msg/Type")


def _referenced_types(owner: str, text: str) -> list[tuple[str, str]]:
    """The message types the fields of a .msg text refer to, in order of appearance."""
    found = []
    for line in text.splitlines():
        match = _FIELD_TYPE.match(line.split("#", 1)[0])
        if not match:
            continue
        base = match.group(1)
        if base in PRIMITIVES:
            continue
        if "/" in base:
            dependency = _split(base)
        elif base == "Header":
            dependency = ("std_msgs", "Header")
        else:
            dependency = (owner, base)
        if dependency not in found:
            found.append(dependency)
    return found


@functools.cache
def _msg_text(package: str, name: str) -> str:
    for prefix in _prefixes():
        path = prefix / "share" / package / "msg" / f"{name}.msg"
        if path.is_file():
            return path.read_text(encoding="utf-8").rstrip("\n")
    raise SettingsError(
        f"no definition of {package}/msg/{name} (share/{package}/msg/{name}.msg) in "
        f"{', '.join(str(p) for p in _prefixes())}"
    )


def _prefixes() -> list[pathlib.Path]:
    ament = [pathlib.Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    return [pathlib.Path(sys.prefix), *ament]
