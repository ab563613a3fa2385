"""The loader: positions of fields, elements and values; load errors with positions and suggestions."""

from pathlib import Path

import pytest
from google.protobuf import text_format
from google.protobuf.text_format import Tokenizer
from hypothesis import given, settings
from hypothesis import strategies as st

from joshua_codegen.check import check_file, check_text
from joshua_codegen.load import load_text
from joshua_codegen.positions import Location
from joshua_codegen.syntax import tokens
from joshua_core.schema import RobotDescription

SEEDS = Path(__file__).parent / "seeds"

SAMPLE = """\
robot_config {
  name: "arm"   # the robot
  mode: MODE_TELEOPERATION
  node {
    type: ENCODER_PUBLISHER
    device_ids: [1, 2,
                 3]
    input_topics: "/a"
    input_topics: "/b"
    env { key: "A" value: "x" }
  }
  node: [{ type: INFERENCE }, { type: CUSTOM }]
  shutdown < sigint_grace_s: 1.5 >
}
"""


def codes_and_positions(result):
    return [(d.code, d.line, d.column) for d in result.diagnostics]


def test_every_field_element_and_value_has_its_position():
    loaded = load_text("r.pbtxt", SAMPLE)
    assert loaded.diagnostics == []
    where = loaded.source_map.get
    assert where(("robot_config",)) == Location("r.pbtxt", 1, 1, 14, 2)
    assert where(("robot_config", "name")) == Location("r.pbtxt", 2, 3, 2, 14)
    assert where(("robot_config", "mode")) == Location("r.pbtxt", 3, 3, 3, 27)
    assert where(("robot_config", "node", 0)) == Location("r.pbtxt", 4, 3, 4, 7)
    assert where(("robot_config", "node", 0, "type")) == Location("r.pbtxt", 5, 5, 5, 28)
    assert where(("robot_config", "node", 0, "device_ids")) == Location("r.pbtxt", 6, 5, 7, 20)
    assert where(("robot_config", "node", 0, "device_ids", 0)) == Location("r.pbtxt", 6, 18, 6, 19)
    assert where(("robot_config", "node", 0, "device_ids", 1)) == Location("r.pbtxt", 6, 21, 6, 22)
    assert where(("robot_config", "node", 0, "device_ids", 2)) == Location("r.pbtxt", 7, 18, 7, 19)
    assert where(("robot_config", "node", 0, "input_topics")) == Location("r.pbtxt", 8, 5, 8, 23)
    assert where(("robot_config", "node", 0, "input_topics", 1)) == Location("r.pbtxt", 9, 19, 9, 23)
    assert where(("robot_config", "node", 0, "env", "A")) == Location("r.pbtxt", 10, 16, 10, 19)
    assert where(("robot_config", "node", 1)) == Location("r.pbtxt", 12, 10, 12, 11)
    assert where(("robot_config", "node", 2, "type")) == Location("r.pbtxt", 12, 33, 12, 45)
    assert where(("robot_config", "shutdown", "sigint_grace_s")) == Location("r.pbtxt", 13, 14, 13, 33)


def test_locate_falls_back_to_the_closest_written_ancestor():
    source = load_text("r.pbtxt", SAMPLE).source_map
    assert source.locate(("robot_config", "node", 1, "topic_name")) == source.get(("robot_config", "node", 1))
    assert source.locate(("robot_config", "ros_domain_id")) == source.get(("robot_config",))
    assert source.locate(("nothing",)) == Location("r.pbtxt", 1, 1)


def test_loaded_message_equals_text_format_parse():
    for path in [*SEEDS.glob("*.pbtxt")]:
        text = path.read_text()
        assert load_text(str(path), text).description == text_format.Parse(text, RobotDescription())
    assert load_text("r", SAMPLE).description == text_format.Parse(SAMPLE, RobotDescription())


def test_columns_count_characters_not_bytes():
    text = 'robot_config {\n  name: "bras_é" mode: MODE_TELEOPERATON\n}\n'
    result = check_text("r.pbtxt", text)
    assert codes_and_positions(result) == [("E004", 2, 24)]


def test_all_load_errors_are_reported_together_with_suggestions():
    text = """\
robot_config {
  nmae: "arm"
  mode: MODE_TELEOPERATON
  sigterm_grace_s: 1
  node {
    type: CAMERA_PUBLISHER
    qos_dept: 5
    qos_reliability: best_effort
    camera_index: 4294967296
  }
}
"""
    result = check_text("r.pbtxt", text)
    assert result.description is None and result.has_errors
    assert codes_and_positions(result) == [
        ("E002", 2, 3),
        ("E004", 3, 9),
        ("E002", 4, 3),
        ("E002", 7, 5),
        ("E004", 8, 22),
        ("E003", 9, 19),
    ]
    messages = [d.message for d in result.diagnostics]
    assert messages[0] == 'unknown field "nmae" in RobotConfig; did you mean "name"?'
    assert messages[2] == 'unknown field "sigterm_grace_s" in RobotConfig; it belongs in shutdown { ... }'
    assert messages[3] == 'unknown field "qos_dept" in Node; did you mean "qos_depth"?'
    assert (
        messages[4] == 'unknown value "best_effort" for qos_reliability (enum Reliability); did you mean "BEST_EFFORT"?'
    )
    assert messages[5] == "camera_index takes an unsigned 32-bit integer (0 to 4294967295), got 4294967296"


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("", ("E006", 1, 1, "the description is empty: expected robot_config { ... }")),
        ("# only a comment\n", ("E006", 1, 1, "the description is empty: expected robot_config { ... }")),
        ("robot_config {\n", ("E001", 1, 1, '"robot_config {" opened here is never closed')),
        (
            "robot_config { name: 'x }",
            ("E001", 1, 22, "unterminated string (a string must close on the line it opens)"),
        ),
        (
            'robot_config { name: "x\\" }',
            ("E001", 1, 22, "unterminated string (a string must close on the line it opens)"),
        ),
        ("robot_config { name = 1 }", ("E001", 1, 21, 'expected ":" or "{" after field name "name", found "="')),
        ("robot_config { } }", ("E001", 1, 18, 'expected a field name, found "}"')),
        ("robot_config { [ext]: 1 }", ("E001", 1, 16, "extension and Any fields ([...]) are not supported")),
        (
            "robot_config { device_ids [1] }",
            ("E002", 1, 16, 'unknown field "device_ids" in RobotConfig; it belongs in node { ... }'),
        ),
        ("robot_config { node { device_ids [1] } }", ("E001", 1, 34, 'expected ":" after field name "device_ids"')),
        ("robot_config { node { device_ids: [1 2] } }", ("E001", 1, 38, 'expected "," or "]" in a list, found "2"')),
        ("robot_config { name: }", ("E001", 1, 22, 'expected a value, found "}"')),
        ("robot_config " + "{ node " * 40, ("E001", 1, 238, "messages nested deeper than 32 levels")),
        ("robot_config { node { qos_depth: 1" + "0" * 500 + " } }", ("E003", 1, 34, None)),
        (
            "robot_config { node { qos_depth: 0x1g } }",
            ("E003", 1, 34, "qos_depth takes an unsigned 32-bit integer, got 0x1g"),
        ),
        (
            'robot_config { name: "\\xff" }',
            ("E003", 1, 22, "string is not valid UTF-8 (write non-ASCII characters directly)"),
        ),
        ('robot_config { name: "\\x" }', ("E003", 1, 22, None)),
        (
            'robot_config { name: "a" name: "b" }',
            ("E005", 1, 26, 'field "name" is given twice in RobotConfig; it takes one value'),
        ),
        (
            "robot_config {}\nrobot_config {}",
            ("E005", 2, 1, 'field "robot_config" is given twice in RobotDescription; it takes one value'),
        ),
        ("robot_config { node: 3 }", ("E003", 1, 22, '"node" is a message: write node { ... }')),
        ('robot_config { name ["a"] }', ("E003", 1, 21, '"name" takes one value, not a list')),
        ("robot_config { shutdown: [{}] }", ("E003", 1, 26, '"shutdown" is not repeated: write shutdown { ... }')),
        ("robot_config { node: [1] }", ("E003", 1, 23, '"node" holds messages: write { ... }, not 1')),
        ("robot_config { name { } }", ("E003", 1, 21, '"name" takes a value, not a message: write name: ...')),
        (
            "camera_index: 1",
            ("E002", 1, 1, 'unknown field "camera_index" in RobotDescription; it belongs in node { ... }'),
        ),
        (
            "robot_configg {}",
            ("E002", 1, 1, 'unknown field "robot_configg" in RobotDescription; did you mean "robot_config"?'),
        ),
        (
            "mode: MODE_TELEOPERATION",
            ("E006", 1, 1, '"mode" belongs inside robot_config { ... }: the file root holds one robot_config block'),
        ),
        ("\x00\x01binary", ("E008", 1, 1, "the file contains a NUL character: is it a binary file?")),
        ('robot_config { name: "a" }\x7f', ("E001", 1, 27, 'expected a field name, found "\x7f"')),
        (
            "robot_config { node { preferred_backend: -4294967294 } }",
            ("E004", 1, 42, "preferred_backend has no value numbered -4294967294; expected one of CPP, PYTHON"),
        ),
    ],
)
def test_load_errors_have_positions_and_clear_messages(text, expected):
    result = check_text("r.pbtxt", text)
    assert result.description is None
    first = next(d for d in result.diagnostics if d.code < "E100")  # rules may report other nodes too
    code, line, column, message = expected
    assert (first.code, first.line, first.column) == (code, line, column)
    if message is not None:
        assert first.message == message


def test_a_byte_order_mark_is_ignored():
    result = check_text("r.pbtxt", "\ufeff" + (SEEDS / "so100_arm.pbtxt").read_text())
    assert not result.has_errors


def test_unreadable_and_non_utf8_files_give_diagnostics(tmp_path):
    missing = check_file(str(tmp_path / "missing.pbtxt"))
    assert [(d.code, d.line, d.column) for d in missing.diagnostics] == [("E007", 1, 1)]
    assert missing.diagnostics[0].message == "cannot read the file: No such file or directory"
    latin1 = tmp_path / "latin1.pbtxt"
    latin1.write_bytes(b'robot_config {\n  name: "bras_articul\xe9"\n}\n')
    result = check_file(str(latin1))
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [("E008", 2, 22)]
    assert result.description is None
    junk = tmp_path / "junk.pbtxt"
    junk.write_bytes(bytes(range(256)) * 4)
    assert check_file(str(junk)).diagnostics[0].code == "E008"


def protobuf_tokens(text: str) -> list[tuple[str, int, int]]:
    """What protobuf's own Tokenizer yields, with the positions of its public ParseError."""
    tokenizer, found = Tokenizer(text.split("\n"), skip_comments=False), []
    while not tokenizer.AtEnd():
        error = tokenizer.ParseError("")
        found.append((tokenizer.token, error.GetLine(), error.GetColumn()))
        tokenizer.NextToken()
    return found


def test_tokens_and_positions_agree_with_protobufs_tokenizer():
    text = 'a: "x"\n  # c\n  b { c: -1 }  d: \'it\\\'s\' e: "open\n  f: 1.5e3 g: [1, -2, .5] # end\n\t\x0c h:"é"'
    assert list(tokens(text)) == protobuf_tokens(text)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("ab_19.+-:{}[]<>,;#'\"\\ \t\n\r\x0b\x0cé\u00a0\u2028")), max_size=60))
def test_tokens_agree_with_protobufs_tokenizer_on_any_text(text):
    assert list(tokens(text)) == protobuf_tokens(text)
