"""Inputs published outside the description: their message type is learnt from the ROS graph."""

import time

import pytest
import rclpy
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from joshua_core.settings import TopicSettings
from joshua_runtime.errors import DeviceError
from joshua_runtime.graph import with_discovered_types
from testsupport.compiled_settings import compiled_settings

DISCOVERY_TIMEOUT_S = 10.0
ABSENT_TIMEOUT_S = 0.3
OUTSIDE_TOPIC = "/outside/joints"
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


@pytest.fixture
def ros_node(ros_domain):
    rclpy.init()
    node = rclpy.create_node("graph_probe")
    yield node
    node.destroy_node()
    rclpy.try_shutdown()


def test_an_unknown_type_is_taken_from_the_publisher_in_the_graph(ros_node):
    publisher_node = rclpy.create_node("outside_publisher")
    publisher_node.create_publisher(JointState, OUTSIDE_TOPIC, RELIABLE)
    topics = [
        TopicSettings(name=OUTSIDE_TOPIC, message_type=""),
        TopicSettings(name="/known", message_type="sensor_msgs/msg/Image"),
    ]
    try:
        resolved = with_discovered_types(ros_node, topics, DISCOVERY_TIMEOUT_S)
    finally:
        publisher_node.destroy_node()
    assert [t.message_type for t in resolved] == ["sensor_msgs/msg/JointState", "sensor_msgs/msg/Image"]
    assert topics[0].message_type == ""  # the settings themselves are left as they were


def test_a_publisher_that_never_appears_is_one_clear_device_error(ros_node):
    started = time.monotonic()
    with pytest.raises(DeviceError, match=r"no publisher of /nobody/here appeared within 0.3 s"):
        with_discovered_types(ros_node, [TopicSettings(name="/nobody/here")], ABSENT_TIMEOUT_S)
    assert time.monotonic() - started >= ABSENT_TIMEOUT_S


def test_compiler_gives_an_outside_input_a_subscription_any_publisher_can_serve():
    settings = compiled_settings(f'''robot_config {{
      name: "r" mode: MODE_DATA_COLLECTION
      node {{ type: MOCK_ENCODER_PUBLISHER topic_name: "/arm" }}
      node {{ type: DATA_SUBSCRIBER topic_name: "/arm" input_topics: ["{OUTSIDE_TOPIC}"] output_directory: "/d" }}
    }}''')
    [outside] = settings["data_subscriber"]["inputs"]
    assert outside == {
        "name": OUTSIDE_TOPIC,  # message_type "" (learnt at run time) is left out, as all zero values
        "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "BEST_EFFORT", "durability": "VOLATILE"},
    }
