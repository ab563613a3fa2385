"""Values that enter generated code stay data: quotes, newlines, `$` or backslashes change nothing."""

import ast
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from joshua_codegen.escape import json_document
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_core.schema import RobotDescription
from joshua_core.schema import robot_config_pb2 as pb
from joshua_core.settings import parse, to_literal

NASTY = st.text(alphabet=st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=40) | st.sampled_from(
    ['"""', "'''", "\n\nimport os; os.system('rm -rf /')", "${HOME}", "\\", "%(here)s", "\r\n#", "\x00", "}}{{"]
)


def settings_literal(source: str) -> dict:
    tree = ast.parse(source)
    assignment = next(n for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "SETTINGS")
    return ast.literal_eval(assignment.value)


@settings(max_examples=150, deadline=None)
@given(output_directory=NASTY, model_path=NASTY, video_source=NASTY, source=NASTY)
def test_strings_reach_the_entrypoint_unchanged(output_directory, model_path, video_source, source):
    description = RobotDescription()
    config = description.robot_config
    config.name, config.mode = "robot", pb.MODE_DATA_COLLECTION
    recorder = config.node.add(name="rec", type=pb.DATA_SUBSCRIBER, topic_name="/t", output_directory=output_directory)
    policy = config.node.add(name="pol", type=pb.INFERENCE, topic_name="/a", model_path=model_path, input_topics=["/t"])
    camera = config.node.add(name="cam", type=pb.MOCK_CAMERA_PUBLISHER, topic_name="/t", video_source=video_source)
    robot = plan(description, source + ".pbtxt")
    files = render(robot)
    for node, field, value in [
        (recorder, "output_directory", output_directory),
        (policy, "model_path", model_path),
        (camera, "video_source", video_source),
    ]:
        text = files[f"nodes/{node.name}.py"]
        compile(text, node.name, "exec")
        assert settings_literal(text).get(field, "") == value  # the contract leaves "" out
        assert settings_literal(text) == to_literal(robot.node(node.name).settings)
        assert parse(settings_literal(text)) == robot.node(node.name).settings
        header = text.splitlines()[:3]
        assert all(line.startswith(("#!", "# ")) for line in header)


@settings(max_examples=100, deadline=None)
@given(source=NASTY | st.text(alphabet="-<>!x", max_size=12))
def test_source_names_cannot_break_the_xml_profile(source):
    from xml.etree import ElementTree

    description = RobotDescription()
    description.robot_config.name, description.robot_config.mode = "robot", pb.MODE_TELEOPERATION
    text = render(plan(description, source + ".pbtxt"))["fastdds_profile.xml"]
    root = ElementTree.fromstring(text.encode())
    assert root.tag == "{http://www.eprosima.com}dds"


@settings(max_examples=200, deadline=None)
@given(
    st.lists(
        st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\0"), max_size=12),
        min_size=1,
        max_size=4,
    )
)
@pytest.mark.process
def test_shell_words_reach_the_program_unchanged(words):
    import subprocess

    from joshua_codegen.escape import shell_word

    script = "printf '%s\\0' " + " ".join(shell_word(word) for word in words)
    printed = subprocess.run(["/bin/sh", "-c", script], capture_output=True, check=True).stdout
    assert printed.decode("utf-8").split("\0")[:-1] == words


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | NASTY,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(NASTY, inner, max_size=4),
    max_leaves=20,
)


@settings(max_examples=300, deadline=None)
@given(value=JSON_VALUES)
def test_the_manifest_json_is_what_the_standard_library_writes(value):
    assert json_document(value) == json.dumps(value, indent=2, ensure_ascii=True)
