"""ROS 2 naming rules for topic and node names, and how a topic name resolves (rclpy-free).

The verdicts match `rclpy.validate_topic_name` + `expand_topic_name` + `validate_full_topic_name`
and `rclpy.validate_node_name`, except that substitutions (`{node}`) are refused and `~` must be
followed by `/`. Nodes run without a namespace, so a relative name `a/b` resolves to `/a/b` and a
private name `~/a` to `/<node>/a`.
"""

from __future__ import annotations

import re

# rmw limit on a fully qualified topic name: 255 minus the 8 characters DDS prefixes reserve.
MAX_TOPIC_LENGTH = 255 - 8
MAX_NODE_NAME_LENGTH = 255
# Node names also name files and systemd units (`joshua-<robot>-<node>.service`, at most 255 bytes).
MAX_UNIT_NODE_NAME_LENGTH = 128

_TOPIC_CHARS = re.compile(r"[^A-Za-z0-9_/~]")
_NODE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def topic_problem(name: str, node_name: str = "node") -> str | None:
    """Why `name` is not a valid topic name for a node without namespace, or None when it is."""
    if not name:
        return "it is empty"
    if "{" in name or "}" in name:
        return "substitutions ({...}) are not supported"
    bad = _TOPIC_CHARS.search(name)
    if bad:
        return f'it contains "{bad.group()}" (allowed: letters, digits, "_", "/" and a leading "~")'
    if "~" in name[1:]:
        return '"~" is allowed only as the first character'
    if name.startswith("~") and len(name) > 1 and name[1] != "/":
        return '"~" must be followed by "/" (e.g. "~/state")'
    if name.endswith("/"):
        return 'it ends with "/"'
    if "//" in name:
        return 'it contains "//"'
    for token in name.split("/"):
        if token[:1].isdigit():
            return f'its part "{token}" starts with a digit'
    if len(resolve_topic(name, node_name)) > MAX_TOPIC_LENGTH:
        return f"it is longer than {MAX_TOPIC_LENGTH} characters once resolved"
    return None


def resolve_topic(name: str, node_name: str) -> str:
    """The fully qualified name of a valid topic name used by `node_name` (no namespace)."""
    if name.startswith("~"):
        return "/" + node_name + name[1:]
    if name.startswith("/"):
        return name
    return "/" + name


def node_name_problem(name: str) -> str | None:
    """Why `name` is not a valid node name here, or None when it is."""
    if not name:
        return "it is empty"
    if name[0].isdigit():
        return "it starts with a digit"
    if not _NODE_NAME.fullmatch(name):
        bad = next(c for c in name if not (c.isascii() and (c.isalnum() or c == "_")))
        return f'it contains "{bad}" (allowed: letters, digits and "_")'
    if len(name) > MAX_UNIT_NODE_NAME_LENGTH:
        return f"it is longer than {MAX_UNIT_NODE_NAME_LENGTH} characters"
    return None
