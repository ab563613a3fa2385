"""check_text and fmt on mutated descriptions: always diagnostics or success, never an exception."""

import math
import re
from pathlib import Path

from google.protobuf import text_format
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from joshua_codegen import defaults
from joshua_codegen.check import check_text, decode
from joshua_codegen.diagnostics import Diagnostic, format_github, format_json, format_text
from joshua_codegen.fmt import format_description
from joshua_codegen.load import load_text
from joshua_codegen.ros_names import node_name_problem, topic_problem
from joshua_core.schema import Node, RobotDescription

HERE = Path(__file__).parent
SEEDS = [p.read_bytes() for p in sorted((HERE / "seeds").glob("*.pbtxt"))]
SEEDS += [p.read_bytes() for p in sorted(HERE.glob("[EW]*/bad.pbtxt")) if p.is_file()][:20]
TOKEN = re.compile(rb'"[^"\n]*"|\'[^\'\n]*\'|#[^\n]*|[A-Za-z_][A-Za-z0-9_]*|-?[0-9][0-9a-zA-Z.+-]*|\S')
VOCABULARY = [
    b"{",
    b"}",
    b"<",
    b">",
    b"[",
    b"]",
    b":",
    b",",
    b";",
    b'"',
    b"'",
    b"#",
    b"\\",
    b"\n",
    b"node",
    b"robot_config",
    b"type",
    b"name",
    b"qos_depth",
    b"device_ids",
    b"MODE_SIMULATION",
    b"CUSTOM",
    b"KEEP_ALL",
    b"-1",
    b"0",
    b"99999999999999999999999",
    b"1e999",
    b"nan",
    b"-inf",
    b'"/a//b"',
    b'"\\xff"',
    b'"\\q"',
    b"\xff",
    b"\x00",
    b"\xe9",
    b"\t",
    b"\r",
    b"true",
    b"0x10",
    b"010",
    b"\xe2\x80\xa8",
]
SETTINGS = settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def assert_clean_outcome(text: str, overrides=()) -> None:
    result = check_text("m.pbtxt", text, overrides)
    assert all(isinstance(d, Diagnostic) and d.line >= 1 and d.column >= 1 for d in result.diagnostics)
    assert all(d.severity in ("error", "warning") for d in result.diagnostics)
    format_text(result.diagnostics, result.sources)
    format_json(result.diagnostics)
    format_github(result.diagnostics)
    loaded = load_text("m.pbtxt", text)
    if loaded.description is not None and "\0" not in text and not text.startswith("\ufeff"):
        # What the loader accepts, text_format accepts with the same result.
        assert text_format.Parse(text, RobotDescription()) == loaded.description
    if not result.has_errors:
        assert_valid_for_later_stages(result.description)
    formatted, problems = format_description(text, "m.pbtxt")
    if formatted is not None:
        assert format_description(formatted, "m.pbtxt") == (formatted, [])
        if loaded.description is not None and not overrides:
            assert load_text("m.pbtxt", formatted).description == loaded.description
    else:
        assert problems


def assert_valid_for_later_stages(description: RobotDescription) -> None:
    """What the model may assume once check found no error."""
    config = description.robot_config
    assert config.name and config.mode
    names = defaults.node_names(config)
    assert len(set(names)) == len(names)
    for node, name in zip(config.node, names):
        assert node_name_problem(name) is None
        assert node.type and Node.DESCRIPTOR.fields_by_name["type"].enum_type.values_by_number.get(node.type)
        for topic in [node.topic_name, node.state_topic, *node.input_topics]:
            assert not topic or topic_problem(topic, name) is None
        assert math.isfinite(defaults.rate_hz(node)) and defaults.rate_hz(node) > 0
        defaults.qos(node), defaults.baud_rate(node), defaults.joint_names(node), defaults.backend(node)


@st.composite
def byte_mutants(draw):
    data = bytearray(draw(st.sampled_from(SEEDS)))
    for _ in range(draw(st.integers(1, 4))):
        where = draw(st.integers(0, len(data)))
        kind = draw(st.sampled_from(["delete", "insert", "replace", "duplicate"]))
        size = draw(st.integers(1, 12))
        if kind == "delete":
            del data[where : where + size]
        elif kind == "insert":
            data[where:where] = draw(st.sampled_from(VOCABULARY) | st.binary(min_size=1, max_size=4))
        elif kind == "replace" and where < len(data):
            data[where] = draw(st.integers(0, 255))
        else:
            data[where:where] = data[where : where + size]
    return bytes(data)


@st.composite
def token_mutants(draw):
    tokens = TOKEN.findall(draw(st.sampled_from(SEEDS)))
    for _ in range(draw(st.integers(1, 4))):
        if not tokens:
            break
        index = draw(st.integers(0, len(tokens) - 1))
        kind = draw(st.sampled_from(["delete", "replace", "duplicate", "swap"]))
        if kind == "delete":
            del tokens[index]
        elif kind == "replace":
            tokens[index] = draw(st.sampled_from(VOCABULARY))
        elif kind == "duplicate":
            tokens.insert(index, tokens[index])
        else:
            other = draw(st.integers(0, len(tokens) - 1))
            tokens[index], tokens[other] = tokens[other], tokens[index]
    return b" ".join(tokens)


@SETTINGS
@given(byte_mutants())
def test_byte_mutations_never_raise(data):
    text, problems = decode("m.pbtxt", data)
    if text is None:
        assert problems[0].code == "E008"
        return
    assert_clean_outcome(text)


@SETTINGS
@given(token_mutants())
def test_token_mutations_never_raise(data):
    text = data.decode("utf-8", errors="replace")
    assert_clean_outcome(text)


SCALARS = st.one_of(
    st.integers(-(2**70), 2**70).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["true", "false", "CPP", "KEEP_ALL", "RELIABLE", "RESTART_NEVER", "CAMERA_PUBLISHER", "x"]),
    st.text(max_size=12).map(lambda s: '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'),
)
NODE_FIELDS = sorted(Node.DESCRIPTOR.fields_by_name)
ROBOT_NAMES = ['"arm"', '"Bad Name"', '""']


@st.composite
def random_field_values(draw):
    name = draw(st.sampled_from(ROBOT_NAMES))
    lines = ["robot_config {", f"  name: {name}", f"  mode: {draw(st.integers(0, 5))}"]
    for _ in range(draw(st.integers(0, 4))):
        lines.append("  node {")
        lines.append(f"    type: {draw(st.integers(0, 12))}")
        for field in draw(st.lists(st.sampled_from(NODE_FIELDS), max_size=6, unique=True)):
            if field in ("type", "env"):
                continue
            lines.append(f"    {field}: {draw(SCALARS)}")
        lines.append("  }")
    lines.append("}")
    overrides = draw(
        st.lists(
            st.sampled_from(
                [
                    "mode=MODE_SIMULATION",
                    "simulation.model=builtin:so100",
                    "name=x",
                    "shutdown.sigint_grace_s=nan",
                    "camera_publisher.qos_depth=0",
                    "custom.args=a,b",
                    "env.A=1",
                    "ros_domain_id=999",
                    "=",
                    "a..b=1",
                ]
            ),
            max_size=3,
        )
    )
    return "\n".join(lines) + "\n", overrides


@SETTINGS
@given(random_field_values())
def test_random_field_values_and_overrides_never_raise(case):
    text, overrides = case
    assert_clean_outcome(text, overrides)
