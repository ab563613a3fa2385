"""The node-type table of docs/description-language.md, rendered from the registry between its marker comments.

    python -m joshua_codegen.readme_tables          # rewrite the table in the page (make docs)
    python -m joshua_codegen.readme_tables --check  # exit 1 when the page's table is stale

tests/test_type_lists.py fails when the committed table differs from what this renders.
"""

import sys
from pathlib import Path

from joshua_core.node_types import NODE_TYPES, NodeTypeSpec
from joshua_core.servo_topics import DIAGNOSTICS_TOPIC

PAGE_NAME = "docs/description-language.md"
PAGE = Path(__file__).resolve().parent.parent / PAGE_NAME
BEGIN = "<!-- begin node-types: rendered from core/joshua_core/node_types.py by `make docs`; do not edit -->"
END = "<!-- end node-types -->"
HEADER = (
    "| type | topic_name | message types (first: default) | requires | opens | also publishes | C++ binary "
    "| in MODE_SIMULATION | extra |",
    "|---|---|---|---|---|---|---|---|---|",
)
NONE = "-"


def _short(message_type: str) -> str:
    return message_type.rsplit("/", 1)[-1]


def _codes(items) -> str:
    return ", ".join(f"`{item}`" for item in items) or NONE


def _opens(entry: NodeTypeSpec) -> str:
    servo_bus = entry.servo_bus and "serial_port" in entry.claims
    return (
        ", ".join(
            f"`{claim}`" + (" (STS3215 servo bus)" if servo_bus and claim == "serial_port" else "")
            for claim in entry.claims
        )
        or NONE
    )


def _also_publishes(entry: NodeTypeSpec) -> str:
    topics = []
    if entry.state_topic:
        topics.append("`state_topic`")
    if entry.odom_topic:
        topics.append("`odom_topic`")
    if entry.diagnostics:
        topics.append(f"`{DIAGNOSTICS_TOPIC}`")
    topics += [f"`{topic.name}`" for topic in entry.fixed_topics]
    return ", ".join(topics) or NONE


def _simulated(entry: NodeTypeSpec) -> str:
    if entry.sim_bridge:
        return "simulated"
    return "runs as it is" if entry.runtime_class else "runs its executable"


def row(entry: NodeTypeSpec) -> str:
    """One table row: what a description author needs to know of a node type."""
    cells = [
        f"`{entry.name}`",
        entry.topic or ("declared in `publishes` / `subscribes`" if entry.declares_topics else NONE),
        ", ".join(_short(t) for t in entry.message_types) or NONE,
        _codes(entry.required),
        _opens(entry),
        _also_publishes(entry),
        f"`{entry.binary}`" if entry.binary else NONE,
        _simulated(entry),
        f"`{entry.runtime_extra}`" if entry.runtime_extra else NONE,
    ]
    return "| " + " | ".join(cells) + " |"


def table() -> str:
    """The rendered section, markers included."""
    rows = [row(entry) for entry in NODE_TYPES.values()]
    return "\n".join((BEGIN, *HEADER, *rows, END))


def render(page_text: str) -> str:
    """The page's text with its table section replaced by a fresh one."""
    start, end = page_text.find(BEGIN), page_text.find(END)
    if start < 0 or end < start:
        raise ValueError(f"{PAGE_NAME} lacks the markers {BEGIN!r} ... {END!r}")
    return page_text[:start] + table() + page_text[end + len(END) :]


def main(argv: list[str]) -> int:
    text = PAGE.read_text(encoding="utf-8")
    fresh = render(text)
    if argv == ["--check"]:
        if fresh != text:
            print(f"{PAGE_NAME}: the node-type table is stale; run: make docs", file=sys.stderr)
            return 1
        return 0
    if argv:
        print("usage: python -m joshua_codegen.readme_tables [--check]", file=sys.stderr)
        return 2
    if fresh != text:
        PAGE.write_text(fresh, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
