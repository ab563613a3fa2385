"""Lists of node types in prose, taken from the registry: what `joshuac explain` and the docs print.

A rule's docstring names the types it concerns with a placeholder ending in `_types`, `{serial_types}`, and its module
defines `TYPE_LISTS = {"serial_types": predicate}` over registry entries; `render` puts the types
that satisfy each predicate in its place, so a new node type appears in every explanation that
concerns it without anyone editing the text (tests/test_type_lists.py fails on a list written by hand).
"""

import re
import textwrap
from collections.abc import Callable, Mapping

from joshua_core.node_types import NODE_TYPES, NodeTypeSpec

Predicate = Callable[[NodeTypeSpec], bool]
PLACEHOLDER = re.compile(r"\{([a-z_]+_types)\}")
MOCKS = "MOCK_*"
# Lines a filled-in paragraph is wrapped to (the width the rules' docstrings are written at).
WIDTH = 100


def types_where(predicate: Predicate) -> list[str]:
    """Names of the schema's node types whose registry entry satisfies the predicate, in registry order."""
    return [name for name, entry in NODE_TYPES.items() if predicate(entry)]


def sentence(names: list[str]) -> str:
    """`A, B and C`; every MOCK_* type at once is written `MOCK_*`, last."""
    mocks = [name for name, entry in NODE_TYPES.items() if entry.mock_of]
    if len(mocks) > 1 and set(mocks) <= set(names):
        names = [name for name in names if name not in mocks] + [MOCKS]
    if len(names) <= 1:
        return "".join(names) or "no node type"
    return f"{', '.join(names[:-1])} and {names[-1]}"


def render(text: str, lists: Mapping[str, Predicate]) -> str:
    """The text with each `{name}` of `lists` replaced by its types. A block of lines of one indentation
    that changed is re-wrapped to WIDTH columns, keeping its indentation."""
    if not lists:
        return text
    blocks: list[list[str]] = []
    for line in text.split("\n"):
        indent = _indent(line) if line.strip() else None
        if blocks and indent is not None and blocks[-1][0].strip() and _indent(blocks[-1][0]) == indent:
            blocks[-1].append(line)
        else:
            blocks.append([line])
    out = []
    for block in blocks:
        joined = "\n".join(block)
        filled = PLACEHOLDER.sub(lambda m: _fill(m, lists), joined)
        if filled != joined:
            indent = _indent(block[0])
            filled = textwrap.fill(
                " ".join(filled.split()), WIDTH, initial_indent=indent, subsequent_indent=indent, break_on_hyphens=False
            )
        out.append(filled)
    return "\n".join(out)


def _indent(line: str) -> str:
    return line[: len(line) - len(line.lstrip())]


def _fill(match: re.Match, lists: Mapping[str, Predicate]) -> str:
    name = match.group(1)
    return sentence(types_where(lists[name])) if name in lists else match.group(0)


def placeholders(text: str) -> set[str]:
    """The placeholder names a text uses."""
    return set(PLACEHOLDER.findall(text))
