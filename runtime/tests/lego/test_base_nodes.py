"""The base node types as processes: the mock drives ideal wheels, the real one fails in one line without its hub."""

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy

from joshua_core.exit_codes import NODE_EXIT_DEVICE
from testsupport.compiled_settings import compiled_node

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def test_the_mock_base_turns_on_the_spot_and_stops_after_the_timeout(start_node, ros_client):
    node = start_node(
        compiled_node('name: "base" type: MOCK_DIFF_DRIVE_BASE topic_name: "/cmd_vel" command_timeout_s: 0.3')
    )
    ros_client.listen("/odom", Odometry, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/odom") is not None, 20.0), node.failure()
    cmd_vel = ros_client.publisher("/cmd_vel", Twist, RELIABLE)
    turn = Twist()
    turn.angular.z = 1.0
    assert ros_client.spin_until(
        lambda: ros_client.last("/odom").twist.twist.angular.z > 0.9, 10.0, every=lambda: cmd_vel.publish(turn)
    )
    assert ros_client.spin_until(lambda: ros_client.last("/odom").twist.twist.angular.z == 0.0, 2.0)
    odom = ros_client.last("/odom")
    assert abs(odom.pose.pose.position.x) < 1e-6 and odom.pose.pose.orientation.z > 0.1
    assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_link")
    code, _, output = node.stop()
    assert code == 0, output


def test_the_base_without_its_hub_exits_with_the_device_code(start_node):
    node = start_node(
        compiled_node(
            'name: "base" type: DIFF_DRIVE_BASE topic_name: "/cmd_vel" ble_transport: "tcp-client:127.0.0.1:1"'
        )
    )
    code, output = node.wait()
    assert code == NODE_EXIT_DEVICE, output
    assert "cannot open Bluetooth controller 'tcp-client:127.0.0.1:1'" in output
    assert "Traceback" not in output
