"""The example descriptions of the spec check clean (legitimate warnings only); a large one stays clean."""

from pathlib import Path

from joshua_codegen.check import check_file, check_text
from joshua_codegen.diagnostics import format_text

SEEDS = Path(__file__).parent / "seeds"


# The spec's camera asks for a C++ binary that no node-type registry entry has.
CAMERA_HAS_NO_BINARY = (
    "CAMERA_PUBLISHER has no C++ binary and always runs its Python entrypoint; preferred_backend CPP is ignored"
)


def test_so100_arm_only_warns_that_nothing_publishes_its_commands_and_its_camera_has_no_binary(monkeypatch):
    monkeypatch.chdir(SEEDS)
    result = check_file("so100_arm.pbtxt")
    assert format_text(result.diagnostics, result.sources) == (
        f"so100_arm.pbtxt:15:5: warning[W102]: {CAMERA_HAS_NO_BINARY}\n"
        "    preferred_backend: CPP\n"
        "    ^~~~~~~~~~~~~~~~~~~~~~\n"
        'so100_arm.pbtxt:20:5: warning[W202]: nothing in this description publishes "/arm/commands"\n'
        '    topic_name: "/arm/commands"\n'
        "    ^~~~~~~~~~~~~~~~~~~~~~~~~~~\n"
        "0 errors, 2 warnings\n"
    )
    assert result.description.robot_config.name == "so100_arm"


def test_so100_leader_follower_only_warns_that_its_camera_has_no_binary(monkeypatch):
    monkeypatch.chdir(SEEDS)
    result = check_file("so100_leader_follower.pbtxt")
    assert [(d.line, d.column, d.code, d.message) for d in result.diagnostics] == [
        (41, 5, "W102", CAMERA_HAS_NO_BINARY)
    ]
    assert [n.type for n in result.description.robot_config.node] == [2, 4, 1, 6]


def large_description(count: int) -> str:
    """`count` nodes in leader/follower/camera triples, each on its own bus, camera and topics."""
    lines = ["robot_config {", '  name: "fleet"', "  mode: MODE_TELEOPERATION"]
    for i in range(count // 3):
        lines += [
            "  node {",
            f'    name: "leader_{i}"',
            "    type: ENCODER_PUBLISHER",
            f'    topic_name: "/arm_{i}/leader"',
            f'    serial_port: "/dev/leader_{i}"',
            "  }",
            "  node {",
            f'    name: "follower_{i}"',
            "    type: ACTUATOR_SUBSCRIBER",
            f'    topic_name: "/arm_{i}/leader"',
            f'    state_topic: "/arm_{i}/state"',
            f'    serial_port: "/dev/follower_{i}"',
            "    device_ids: [1, 2, 3, 4, 5, 6]",
            "  }",
            "  node {",
            f'    name: "camera_{i}"',
            "    type: CAMERA_PUBLISHER",
            f'    topic_name: "/arm_{i}/image"',
            f"    camera_index: {i}",
            "  }",
        ]
    lines.append("}")
    return "\n".join(lines) + "\n"


def test_a_thousand_node_description_checks_clean():
    result = check_text("fleet.pbtxt", large_description(1002))
    assert result.diagnostics == []
    assert len(result.description.robot_config.node) == 1002
