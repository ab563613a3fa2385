"""Leader/follower teleoperation end to end: two emulated SO-100 buses, the two nodes as processes.

The nodes get the settings joshuac writes for config/robots/so100_leader_follower.pbtxt (ENCODER_PUBLISHER
on the leader bus publishing /leader/joint_states RELIABLE; ACTUATOR_SUBSCRIBER on the follower bus
subscribing to it), with the serial ports set to the emulators' ptys as `--set` would.
"""

import signal
from pathlib import Path

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from servo_helpers import SO100_IDS, SO100_JOINTS

from joshua_runtime.drivers.calibration import RADIANS_PER_TICK
from testsupport.compiled_settings import compiled_settings

STARTUP_TIMEOUT_S = 30.0
TRACKING_TIMEOUT_S = 10.0
TRACKING_TOLERANCE_TICKS = 2
LEADER_TOPIC = "/leader/joint_states"
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
POSES = ([1200, 1800, 2600, 3000, 900, 2300], [2900, 2200, 1500, 1100, 3600, 1700])
ROBOT = Path(__file__).resolve().parents[3] / "config" / "robots" / "so100_leader_follower.pbtxt"


def test_follower_tracks_the_leader(emulators, start_node, ros_client):
    leader_bus = emulators("ttyUSB0")
    follower_bus = emulators("ttyUSB1")
    settings = compiled_settings(
        ROBOT.read_text(),
        [f"encoder_publisher.serial_port={leader_bus.link}", f"actuator_subscriber.serial_port={follower_bus.link}"],
        path=str(ROBOT),
    )
    leader = start_node(settings["encoder_publisher"])
    follower = start_node(settings["actuator_subscriber"])
    ros_client.listen(LEADER_TOPIC, JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last(LEADER_TOPIC) is not None, STARTUP_TIMEOUT_S), (
        leader.failure(),
        follower.failure(),
    )
    (publisher,) = ros_client.publishers_info(LEADER_TOPIC, STARTUP_TIMEOUT_S)
    assert (publisher.node_name, publisher.topic_type) == ("encoder_publisher", "sensor_msgs/msg/JointState")
    assert publisher.qos_profile.reliability == ReliabilityPolicy.RELIABLE
    assert publisher.qos_profile.durability == DurabilityPolicy.VOLATILE
    followers = ros_client.subscriptions_info(LEADER_TOPIC, STARTUP_TIMEOUT_S)  # the client's own left out
    assert [(s.node_name, s.topic_type) for s in followers] == [("actuator_subscriber", "sensor_msgs/msg/JointState")]
    assert followers[0].qos_profile.reliability == ReliabilityPolicy.RELIABLE
    assert [follower_bus.read_register(i, "Torque_Enable") for i in SO100_IDS] == [1] * 6
    assert [leader_bus.read_register(i, "Torque_Enable") for i in SO100_IDS] == [0] * 6

    for pose in POSES:
        for servo_id, ticks in zip(SO100_IDS, pose):
            leader_bus.move_by_hand(servo_id, ticks)

        def tracking(pose=pose):
            return all(abs(follower_bus.position(i) - t) <= TRACKING_TOLERANCE_TICKS for i, t in zip(SO100_IDS, pose))

        assert follower_bus.wait_until(tracking, TRACKING_TIMEOUT_S), [follower_bus.position(i) for i in SO100_IDS]
        assert [follower_bus.read_register(i, "Goal_Position") for i in SO100_IDS] == pose

        def published_pose(pose=pose):
            message = ros_client.last(LEADER_TOPIC)
            expected = [(t - 2047.5) * RADIANS_PER_TICK for t in pose]
            return all(abs(p - e) < 1e-9 for p, e in zip(message.position, expected))

        assert ros_client.spin_until(published_pose, TRACKING_TIMEOUT_S)
        assert list(ros_client.last(LEADER_TOPIC).name) == SO100_JOINTS

    for node in (leader, follower):
        code, _, stderr = node.stop(signal.SIGINT)
        assert code == 0, stderr
    assert [follower_bus.read_register(i, "Torque_Enable") for i in SO100_IDS] == [0] * 6
