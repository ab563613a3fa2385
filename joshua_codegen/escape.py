"""Escaping of values that enter generated files: one function per target language."""

import json


def python_literal(value, indent: int = 0) -> str:
    """A Python expression that evaluates to `value` (dicts, lists, str, int, float, bool, None).

    Strings go through repr(), so quotes, newlines, backslashes and `$` stay data. Dicts keep their
    insertion order (deterministic); one key per line for readable diffs.
    """
    pad = " " * indent
    inner = " " * (indent + 4)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{inner}{python_literal(str(k))}: {python_literal(v, indent + 4)}," for k, v in value.items()]
        return "{\n" + "\n".join(items) + f"\n{pad}}}"
    if isinstance(value, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in value):
            return "[" + ", ".join(python_literal(v) for v in value) + "]"
        items = [f"{inner}{python_literal(v, indent + 4)}," for v in value]
        return "[\n" + "\n".join(items) + f"\n{pad}]"
    if value is None or isinstance(value, (bool, int)):
        return repr(value)
    if isinstance(value, float):
        return repr(value) if value == value and abs(value) != float("inf") else f"float({str(value)!r})"
    if isinstance(value, str):
        return repr(value)
    raise TypeError(f"cannot write {type(value).__name__} as a Python literal")


def one_line(text: str) -> str:
    """Text safe inside a one-line comment of any target: control characters become escapes."""
    return json.dumps(text, ensure_ascii=True)[1:-1]


def dot_id(text: str) -> str:
    """A quoted Graphviz DOT identifier."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def mermaid_label(text: str) -> str:
    """A quoted Mermaid label; quotes and brackets become HTML entities Mermaid understands."""
    replacements = {"&": "&amp;", '"': "&quot;", "<": "&lt;", ">": "&gt;", "\n": " ", "#": "&num;"}
    return '"' + "".join(replacements.get(ch, ch) for ch in text) + '"'
