"""A base broadcasts its odometry as the transform odom -> base_link on /tf."""

from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy

from testsupport.compiled_settings import compiled_node

RELIABLE = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
WAIT_S = 20.0


def test_the_mock_base_publishes_odom_to_base_link_on_tf(start_node, ros_client):
    from tf2_msgs.msg import TFMessage

    node = start_node(compiled_node('name: "base" type: MOCK_DIFF_DRIVE_BASE topic_name: "/cmd_vel"'))
    ros_client.listen("/odom", Odometry, RELIABLE, keep=100)
    ros_client.listen("/tf", TFMessage, RELIABLE, keep=100)
    assert ros_client.spin_until(lambda: ros_client.count("/tf") >= 5 and ros_client.count("/odom") >= 5, WAIT_S), (
        node.failure()
    )
    odometry = {(m.header.stamp.sec, m.header.stamp.nanosec): m for m in ros_client.messages("/odom")}
    matched = 0
    for message in ros_client.messages("/tf"):
        [transform] = message.transforms
        assert (transform.header.frame_id, transform.child_frame_id) == ("odom", "base_link")
        odom = odometry.get((transform.header.stamp.sec, transform.header.stamp.nanosec))
        if odom is not None:
            assert transform.transform.translation.x == odom.pose.pose.position.x
            assert transform.transform.rotation == odom.pose.pose.orientation
            matched += 1
    assert matched >= 3
