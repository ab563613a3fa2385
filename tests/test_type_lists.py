"""Lists of node types are rendered from the registry, never written by hand.

`joshuac explain` fills each rule's placeholders from the registry, the node-type table of
docs/description-language.md is rendered by `make docs`, and a scan of the repository's code, docs and
schema fails on any other sequence of three or more node type names, the form a hand-written list takes.
"""

import dataclasses
import re
import subprocess
from pathlib import Path

import pytest

from joshua_codegen import readme_tables, type_lists
from joshua_codegen.rules import all_rules, explain
from joshua_core.node_types import NODE_TYPES

ROOT = Path(__file__).resolve().parent.parent
TYPE_NAME = re.compile(r"\b(?:" + "|".join(sorted(NODE_TYPES, key=len, reverse=True)) + r")\b|\bMOCK_\*")
# Mentions this far apart (or across a sentence or paragraph end) belong to different sentences.
LIST_GAP_CHARS = 60
LIST_LENGTH = 3
# Where node type names are defined rather than listed: the registry, the schema's enum and its
# generated modules. Tests name types on purpose; generated/ and the web page are built output.
DEFINITIONS = {"core/joshua_core/node_types.py"}
SKIPPED_PREFIXES = ("tests/", "runtime/tests/", "generated/", "web/")
SKIPPED_SUFFIXES = ("_pb2.py", "_pb2.pyi", ".lock", ".pbtxt", ".png", ".jpg", ".xml", ".urdf", ".mp4")
NODE_TYPE_ENUM = re.compile(r"^enum NodeType \{.*?^\}", re.MULTILINE | re.DOTALL)
LINE_START = re.compile(r"^[ \t#/*|>-]*$")


def hand_written_lists(text: str) -> list[tuple[int, list[str]]]:
    """(line, names) of every run of LIST_LENGTH or more different type names written as a list: close
    together within one sentence, or opening the rows of a table."""
    found = []
    for paragraph in re.finditer(r"(?:[^\n]|\n(?!\s*\n))+", text):
        mentions = list(TYPE_NAME.finditer(paragraph.group(0)))
        runs = _table_rows(paragraph.group(0), mentions)
        run: list[re.Match] = []
        for mention in mentions:
            gap = paragraph.group(0)[run[-1].end() : mention.start()] if run else ""
            if run and (len(gap) > LIST_GAP_CHARS or re.search(r"[.;:]\s", gap)):
                runs.append(run)
                run = []
            run.append(mention)
        runs.append(run)
        for names in runs:
            if len({m.group(0) for m in names}) >= LIST_LENGTH:
                line = text.count("\n", 0, paragraph.start() + names[0].start()) + 1
                found.append((line, [m.group(0) for m in names]))
    return found


def _table_rows(text: str, mentions: list[re.Match]) -> list[list[re.Match]]:
    """Runs of mentions that each open a line, on lines that follow one another or are continued by
    lines indented deeper (a table row wrapped under its text column)."""
    lines = text.split("\n")
    runs: list[list[re.Match]] = [[]]
    previous = None
    for mention in mentions:
        line = text.count("\n", 0, mention.start())
        before = lines[line][: mention.start() - (text.rfind("\n", 0, mention.start()) + 1)]
        if not LINE_START.match(before):
            continue
        indent = len(before) - len(before.lstrip(" \t"))
        continued = previous is not None and all(
            len(between) - len(between.lstrip(" \t")) > previous[1] for between in lines[previous[0] + 1 : line]
        )
        if previous is not None and not continued:
            runs.append([])
        runs[-1].append(mention)
        previous = (line, indent)
    return runs


def scanned_files() -> list[Path]:
    listed = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    return [
        ROOT / name
        for name in listed.split()
        if not name.startswith(SKIPPED_PREFIXES) and not name.endswith(SKIPPED_SUFFIXES) and name not in DEFINITIONS
    ]


def without_rendered_parts(path: Path, text: str) -> str:
    """The text less what is generated from the registry or defines the names."""
    start, end = text.find(readme_tables.BEGIN), text.find(readme_tables.END)
    if start >= 0 and end > start:
        text = text[:start] + "\n" * text.count("\n", start, end) + text[end:]
    if path.suffix == ".proto":
        text = NODE_TYPE_ENUM.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    return text


@pytest.mark.process
def test_no_code_doc_or_schema_comment_lists_node_types_by_hand():
    offenders = []
    for path in scanned_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError):
            continue
        for line, names in hand_written_lists(without_rendered_parts(path, text)):
            offenders.append(f"{path.relative_to(ROOT)}:{line}: {', '.join(names)}")
    assert not offenders, (
        "node types listed by hand; render the list from the registry (a rule's TYPE_LISTS placeholder, the "
        "node-type table of `make docs`) or point at it:\n" + "\n".join(offenders)
    )


@pytest.mark.parametrize(
    "text, listed",
    [
        ("ENCODER_PUBLISHER, ACTUATOR_SUBSCRIBER and LIDAR_PUBLISHER set it", True),
        ("types (INFERENCE,\n    DATA_SUBSCRIBER, MOCK_* and CUSTOM) ignore it", True),
        (
            "    ENCODER_PUBLISHER   states at rate_hz, in the units the driver uses\n"
            "    CAMERA_PUBLISHER    rendered frames of the model camera named like frame_id\n"
            "    LIDAR_PUBLISHER     360 rays cast in the plane of the lidar site\n",
            True,
        ),
        ("An INFERENCE node feeds an ACTUATOR_SUBSCRIBER. A CAMERA_PUBLISHER, elsewhere, is unrelated.", False),
        ("ENCODER_PUBLISHER and ACTUATOR_SUBSCRIBER", False),
    ],
)
def test_the_scan_tells_a_list_from_prose(text, listed):
    assert bool(hand_written_lists(text)) == listed


def test_the_node_type_table_is_rendered_from_the_registry():
    text = readme_tables.PAGE.read_text(encoding="utf-8")
    assert readme_tables.render(text) == text, (
        f"{readme_tables.PAGE_NAME}: the node-type table is stale; run: make docs"
    )
    for name in NODE_TYPES:
        assert f"| `{name}` |" in text


def test_explain_e105_names_every_type_that_needs_a_serial_port():
    text = " ".join(explain("E105").split())
    needs = [name for name, entry in NODE_TYPES.items() if "serial_port" in entry.required]
    assert len(needs) >= LIST_LENGTH
    for name in NODE_TYPES:
        assert (re.search(rf"\b{name}\b", text) is not None) == (name in needs), name


def test_a_new_type_appears_in_every_explanation_that_concerns_it(monkeypatch):
    serial = dataclasses.replace(NODE_TYPES["LIDAR_PUBLISHER"], name="SONAR_PUBLISHER", cpp_parameters=None)
    monkeypatch.setitem(NODE_TYPES, serial.name, serial)
    assert "SONAR_PUBLISHER" in explain("E105") and "SONAR_PUBLISHER" in explain("E401")
    assert "SONAR_PUBLISHER" in explain("W102")
    assert "SONAR_PUBLISHER" in readme_tables.table()


@pytest.mark.parametrize("module", all_rules(), ids=lambda m: m.CODE)
def test_every_placeholder_of_a_rule_is_filled_from_the_registry(module):
    lists = getattr(module, "TYPE_LISTS", {})
    assert type_lists.placeholders(module.__doc__) == set(lists)
    rendered = explain(module.CODE)
    assert not type_lists.placeholders(rendered) & set(lists)
    for predicate in lists.values():
        assert type_lists.types_where(predicate), f"{module.CODE}: a placeholder that names no type"
