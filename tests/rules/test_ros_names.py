"""Topic and node name rules agree with rclpy's validators (rclpy only in tests)."""

from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.exceptions import InvalidNodeNameException, InvalidTopicNameException
from rclpy.expand_topic_name import expand_topic_name
from rclpy.validate_full_topic_name import validate_full_topic_name
from rclpy.validate_node_name import validate_node_name
from rclpy.validate_topic_name import validate_topic_name

from joshua_codegen.ros_names import MAX_UNIT_NODE_NAME_LENGTH, node_name_problem, resolve_topic, topic_problem

NODE = "arm_node"
TOPIC_CHARACTERS = "ab_Z09/~ -.é"


def rclpy_accepts_topic(name: str) -> bool:
    try:
        validate_topic_name(name)
        validate_full_topic_name(expand_topic_name(name, NODE, "/"))
    except InvalidTopicNameException:
        return False
    return True


def rclpy_accepts_node(name: str) -> bool:
    try:
        validate_node_name(name)
    except InvalidNodeNameException:
        return False
    return True


@settings(max_examples=400, deadline=None)
@given(st.text(alphabet=TOPIC_CHARACTERS, max_size=12))
def test_topic_verdicts_match_rclpy(name):
    ours = topic_problem(name, NODE) is None
    # Stricter than rclpy on purpose: "~name" (rclpy expands it to "/arm_nodename").
    if name.startswith("~") and len(name) > 1 and name[1] != "/":
        assert not ours
        return
    assert ours == rclpy_accepts_topic(name), name
    if ours:
        assert resolve_topic(name, NODE) == expand_topic_name(name, NODE, "/")


def test_substitutions_and_overlong_names_are_refused():
    assert topic_problem("/{node}/state") == "substitutions ({...}) are not supported"
    assert topic_problem("/" + "a" * 246) is None
    assert topic_problem("/" + "a" * 247) == "it is longer than 247 characters once resolved"
    assert not rclpy_accepts_topic("/" + "a" * 247)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="aZ_09-é .", max_size=10))
def test_node_name_verdicts_match_rclpy(name):
    assert (node_name_problem(name) is None) == rclpy_accepts_node(name), name


def test_node_names_are_capped_for_unit_file_names():
    assert node_name_problem("a" * MAX_UNIT_NODE_NAME_LENGTH) is None
    assert node_name_problem("a" * (MAX_UNIT_NODE_NAME_LENGTH + 1)) == "it is longer than 128 characters"
