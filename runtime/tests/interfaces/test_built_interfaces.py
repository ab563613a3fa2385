"""Interface packages built by set-up (tf2_msgs) work like the wheels' ones, and every catalogued type imports."""

import subprocess
import sys
import textwrap

import pytest
from geometry_msgs.msg import TransformStamped
from joshua_runtime.messages import message_class
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message, serialize_message

from joshua_codegen.msg_catalog import MESSAGE_TYPES

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
RECEIVE_TIMEOUT_S = 15.0
PUBLISHER_RUN_S = 20.0


@pytest.mark.parametrize("message_type", sorted(MESSAGE_TYPES))
def test_every_catalogued_message_type_imports_and_round_trips(message_type):
    cls = message_class(message_type)
    assert deserialize_message(serialize_message(cls()), cls) == cls()


def test_tf2_services_and_actions_import():
    from tf2_msgs.action import LookupTransform
    from tf2_msgs.msg import TF2Error
    from tf2_msgs.srv import FrameGraph

    assert FrameGraph.Response(frame_yaml="a: b").frame_yaml == "a: b"
    assert LookupTransform.Result().error.error == TF2Error.NO_ERROR


def test_a_tf_message_published_in_another_process_arrives(ros_env, ros_client):
    """TFMessage goes over DDS with the built Fast DDS typesupport: another process publishes, this one receives."""
    from tf2_msgs.msg import TFMessage

    publisher = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import time, rclpy
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        from geometry_msgs.msg import TransformStamped
        from tf2_msgs.msg import TFMessage
        rclpy.init()
        node = rclpy.create_node("tf_source")
        pub = node.create_publisher(TFMessage, "/tf", QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
        moved = TransformStamped(child_frame_id="gripper")
        moved.header.frame_id = "base_link"
        moved.transform.translation.x = 0.25
        moved.transform.rotation.z, moved.transform.rotation.w = 0.6, 0.8
        deadline = time.monotonic() + {PUBLISHER_RUN_S}
        while time.monotonic() < deadline:
            pub.publish(TFMessage(transforms=[moved]))
            time.sleep(0.05)
    """)], env=ros_env)
    try:
        ros_client.listen("/tf", TFMessage, RELIABLE)
        assert ros_client.spin_until(lambda: ros_client.last("/tf") is not None, RECEIVE_TIMEOUT_S)
    finally:
        publisher.kill()
        publisher.wait()
    [received] = ros_client.last("/tf").transforms
    assert isinstance(received, TransformStamped)
    assert (received.header.frame_id, received.child_frame_id) == ("base_link", "gripper")
    assert (received.transform.translation.x, received.transform.rotation.z, received.transform.rotation.w) == (0.25, 0.6, 0.8)
