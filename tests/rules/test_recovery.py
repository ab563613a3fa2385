"""One run shows every problem it can: unclosed blocks at their opening, rules past errors in nodes."""

from joshua_codegen.check import check_text
from joshua_codegen.diagnostics import format_text

HEAD = 'robot_config {\n  name: "r"\n  mode: MODE_TELEOPERATION\n'


def found(text: str) -> list[tuple[str, int, int]]:
    result = check_text("r.pbtxt", text)
    return [(d.code, d.line, d.column) for d in result.diagnostics]


def test_an_unclosed_node_is_reported_at_its_opening_and_the_rest_is_checked():
    text = HEAD + (
        "  node {\n"  # 4: never closed
        "    type: MOCK_ENCODER_PUBLISHER\n"
        '    topic_name: "/arm/joint_states"\n'
        "    qos_reliability: BEST_EFFORT\n"
        "\n"
        "  node {\n"  # 9
        "    type: MOCK_ACTUATOR_SUBSCRIBER\n"
        '    topic_name: "/arm/joint_states"\n'
        "    qos_reliability: RELIABLE\n"  # 12: E301
        "  }\n"
        "}\n"
    )
    result = check_text("r.pbtxt", text)
    assert [(d.code, d.line, d.column, d.end_column) for d in result.diagnostics] == [
        ("E001", 4, 3, 9),
        ("E301", 12, 5, 30),
    ]
    unclosed = result.diagnostics[0]
    assert unclosed.message == '"node {" opened here is never closed'
    assert [(r.line, r.column) for r in unclosed.related] == [(9, 3), (15, 1)]
    assert "the end of the file is reached" in unclosed.related[1].message
    assert result.description is None


def test_two_unclosed_nodes_are_both_found():
    text = HEAD + (
        "  node {\n"  # 4
        "    type: MOCK_CAMERA_PUBLISHER\n"
        "  node {\n"  # 6
        "    type: MOCK_CAMERA_PUBLISHER\n"
        '    topic_name: "bad topic"\n'  # 8: E203
        "}\n"
    )
    assert found(text) == [("E001", 4, 3), ("E104", 4, 3), ("E001", 6, 3), ("E203", 8, 5)]


def test_an_unclosed_block_on_one_line_is_the_innermost_one_open():
    result = check_text("r.pbtxt", 'robot_config { name: "r" node { type: CUSTOM }')
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [("E001", 1, 1)]
    assert result.diagnostics[0].message == '"robot_config {" opened here is never closed'


def test_a_syntax_error_in_one_node_does_not_hide_the_other_nodes():
    text = HEAD + (
        "  node {\n"
        "    type: MOCK_CAMERA_PUBLISHER\n"
        '    topic_name "/camera"\n'  # 6: E001
        "  }\n"
        "  node {\n"
        "    type: MOCK_ENCODER_PUBLISHER\n"
        '    topic_name: "/a//b"\n'  # 10: E203
        "  }\n"
        "}\n"
    )
    assert found(text) == [("E001", 6, 16), ("E203", 10, 5)]


def test_schema_errors_in_one_node_do_not_hide_qos_errors_elsewhere():
    text = HEAD + (
        "  node {\n"
        "    type: MOCK_CAMERA_PUBLISHR\n"  # 5: E004
        "    qos_dept: 3\n"  # 6: E002
        "  }\n"
        "  node {\n"
        "    type: MOCK_ENCODER_PUBLISHER\n"
        '    topic_name: "/j"\n'
        "    qos_reliability: BEST_EFFORT\n"
        "  }\n"
        "  node {\n"
        "    type: MOCK_ACTUATOR_SUBSCRIBER\n"
        '    topic_name: "/j"\n'
        "    qos_reliability: RELIABLE\n"  # 16: E301
        "  }\n"
        "}\n"
    )
    result = check_text("r.pbtxt", text)
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [
        ("E004", 5, 11),
        ("E002", 6, 5),
        ("E301", 16, 5),
    ]
    assert "did you mean" in format_text(result.diagnostics, result.sources)


def test_an_unknown_node_hides_no_publisher_and_invents_no_missing_one():
    """The subscriber's topic may be what the unknown node publishes: no W202, no E103 for the broken node."""
    text = HEAD.replace("MODE_TELEOPERATION", "MODE_INFERENCE") + (
        "  node {\n"
        "    type: INFERENCE\n"
        '    topic_name: "/cmd"\n'
        '    input_topics: ["/camera"]\n'
        '    model_path: "/models/act"\n'
        '    devise: "cpu"\n'  # 9: E002, the node is unknown
        "  }\n"
        "  node {\n"
        "    type: MOCK_ACTUATOR_SUBSCRIBER\n"
        '    topic_name: "/cmd"\n'
        "  }\n"
        "}\n"
    )
    assert found(text) == [("E002", 9, 5)]


def test_errors_outside_the_nodes_stop_before_the_rules():
    text = HEAD.replace("MODE_TELEOPERATION", "MODE_TELEOP") + ('  node {\n    topic_name: "/a//b"\n  }\n}\n')
    assert found(text) == [("E004", 3, 9)]
