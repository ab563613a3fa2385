"""A Foxglove client that connects after the robot started gets the messages kept for late subscribers.

The robot (testsupport/latched_robot.py) is a generated one run by its supervisor; its
ROBOT_STATE_PUBLISHER sent /tf_static and /robot_description once, before any client was there.
Each round is a new client, as each Foxglove window is.
"""

import asyncio

from rclpy.serialization import deserialize_message
from std_msgs.msg import String

from testsupport.foxglove_client import first_messages, free_port
from testsupport.latched_robot import latched_robot
from testsupport.running_robot import running_robot

ROUNDS = 3
LATE_CLIENT_WAIT_S = 10.0  # a latched message is due at once; live topics arrive within a period
LATCHED = ["/tf_static", "/robot_description"]
DISCOVERED_WAIT_S = 20.0  # the bridge looks for new topics every 2 s


def test_every_late_client_receives_the_latched_messages(tmp_path, ros_env):
    from tf2_msgs.msg import TFMessage

    port = free_port()
    with running_robot(latched_robot(ros_env["ROS_DOMAIN_ID"], tmp_path / "bags", port), tmp_path, ros_env):
        for round_ in range(ROUNDS):
            try:
                channels, payloads = asyncio.run(first_messages(port, LATCHED, LATE_CLIENT_WAIT_S))
            except TimeoutError:
                raise AssertionError(f"round {round_ + 1}: no latched message in {LATE_CLIENT_WAIT_S} s") from None
            assert [t.child_frame_id for t in deserialize_message(payloads["/tf_static"], TFMessage).transforms] == [
                "laser"
            ]
            assert "<robot" in deserialize_message(payloads["/robot_description"], String).data
            assert channels["/tf_static"]["schemaName"] == "tf2_msgs/msg/TFMessage"


def test_a_latched_topic_published_outside_the_description_is_kept_too(tmp_path, ros_env, ros_client):
    """Discovered topics are subscribed with their publishers' QoS: transient local here."""
    port = free_port()
    with running_robot(latched_robot(ros_env["ROS_DOMAIN_ID"], tmp_path / "bags", port), tmp_path, ros_env):
        kept = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}
        ros_client.publisher("/map_name", String, kept).publish(String(data="kitchen"))
        for _ in range(2):  # the second client joins after the first took the message
            _, payloads = asyncio.run(first_messages(port, ["/map_name"], DISCOVERED_WAIT_S))
            assert deserialize_message(payloads["/map_name"], String).data == "kitchen"
