"""`joshuac fmt`: canonical layout, comments kept, idempotent, meaning unchanged."""

import re
from pathlib import Path

import pytest
from google.protobuf import text_format

from joshua_codegen.fleet.load import is_fleet_text
from joshua_codegen.fmt import format_description, quote
from joshua_core.schema import FleetDescription, RobotDescription

HERE = Path(__file__).parent
SEEDS = sorted((HERE / "seeds").glob("*.pbtxt"))
# Fixtures that parse as text format (all but the syntax, encoding and unreadable-file ones).
FIXTURES = sorted(p for p in HERE.glob("[EW]*/bad.pbtxt") if p.is_file() and p.parent.name not in ("E001", "E008"))

MESSY = """\
# Header comment.

robot_config <  # the robot
    name: 'so100' "_arm" , # joined strings
  mode: MODE_TELEOPERATION;
  node {
        type: CAMERA_PUBLISHER
    # the servos
    device_ids: [1, # first
      2]
    args: ["tab\\there", "\\303\\251t\\u00e9", "\\\\q", 'it\\'s']


  }
  node: [{type: ENCODER_PUBLISHER}, <type: INFERENCE>]  # two nodes
  # before shutdown
  shutdown {}
  simulation { # sim
  }
>
# Trailer.
"""

CANONICAL = """\
# proto-file: joshua/v1/robot_config.proto
# proto-message: joshua.v1.RobotDescription
# Header comment.

robot_config {  # the robot
  name: "so100_arm"  # joined strings
  mode: MODE_TELEOPERATION

  node {
    type: CAMERA_PUBLISHER
    # the servos
    # first
    device_ids: [1, 2]
    args: ["tab\\there", "été", "\\\\q", "it's"]
  }

  node {
    type: ENCODER_PUBLISHER
  }

  node {
    type: INFERENCE
  }  # two nodes

  # before shutdown
  shutdown {}
  simulation {  # sim
  }
}
# Trailer.
"""


HEADER = ["proto-file: joshua/v1/robot_config.proto", "proto-message: joshua.v1.RobotDescription"]
FLEET_HEADER = ["proto-file: joshua/v1/fleet_config.proto", "proto-message: joshua.v1.FleetDescription"]


def comments(text):
    return [line.split("#", 1)[1].strip() for line in text.splitlines() if "#" in line]


def without_header(found):
    return [comment for comment in found if comment not in HEADER + FLEET_HEADER]


def test_messy_text_gets_the_canonical_layout():
    formatted, diagnostics = format_description(MESSY, "r.pbtxt")
    assert diagnostics == []
    assert formatted == CANONICAL


@pytest.mark.parametrize("path", SEEDS + FIXTURES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_formatting_is_idempotent_and_keeps_meaning_and_comments(path):
    text = path.read_text()
    formatted, diagnostics = format_description(text, path.name)
    assert diagnostics == []
    assert format_description(formatted, path.name) == (formatted, [])
    header, root = (FLEET_HEADER, FleetDescription) if is_fleet_text(text) else (HEADER, RobotDescription)
    assert comments(formatted)[:2] == header  # the schema header, of the file's own schema, comes first
    assert comments(formatted)[2:] == without_header(comments(text))
    try:
        original = text_format.Parse(text, root())
    except text_format.ParseError:
        return  # fixtures with unknown fields or bad values: layout only
    assert text_format.Parse(formatted, root()) == original


def test_seeds_are_already_canonical_apart_from_nothing():
    for path in SEEDS:
        assert format_description(path.read_text(), path.name)[0] == path.read_text()


def test_messy_text_keeps_its_meaning():
    formatted, _ = format_description(MESSY, "r.pbtxt")
    assert text_format.Parse(formatted, RobotDescription()) == text_format.Parse(MESSY, RobotDescription())
    assert format_description(formatted, "r.pbtxt")[0] == formatted


@pytest.mark.parametrize(
    ("text", "code", "line", "column"),
    [
        ("robot_config {", "E001", 1, 15),
        ('robot_config { name: "x }', "E001", 1, 22),
        ('robot_config { name: "\\x" }', "E003", 1, 22),
        ('robot_config { name: "\\q" }', "E003", 1, 22),
        ("robot_config {\n\0}", "E008", 2, 1),
    ],
)
def test_unformattable_text_gives_diagnostics(text, code, line, column):
    formatted, diagnostics = format_description(text, "r.pbtxt")
    assert formatted is None
    assert [(d.code, d.line, d.column) for d in diagnostics] == [(code, line, column)]


def test_the_header_is_written_once_and_replaces_another_schema():
    text = "# proto-message: other.Message\n# mine\nrobot_config {}\n"
    formatted, _ = format_description(text, "r.pbtxt")
    assert formatted.splitlines() == [f"# {HEADER[0]}", f"# {HEADER[1]}", "# mine", "robot_config {}"]
    assert format_description(formatted, "r.pbtxt")[0] == formatted


def test_quote_escapes_canonically():
    assert quote(b'a"b\\c\nd\te\r') == '"a\\"b\\\\c\\nd\\te\\r"'
    assert quote("é\x01\x7f\u2028".encode()) == '"é\\001\\177\\342\\200\\250"'
    assert quote(b"\xff") == '"\\377"'
    assert re.fullmatch(r'"[^\n]*"', quote(bytes(range(256))))
