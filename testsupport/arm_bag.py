"""A bag written by the project's bag writer, for the dataset tests: an arm session whose values say their moment.

A leader's JointState (the action), a follower's JointState and a camera's Image, `hz` messages a
second for `seconds`; the leader's and follower's first positions count the messages and every pixel
of image i is i % 256, so each frame of a dataset made from it shows which moment of the bag it holds.
"""

import time
from pathlib import Path

import numpy as np

LEADER, FOLLOWER, CAMERA = "/leader/joint_states", "/follower/joint_states", "/camera/image_raw"
JOINTS = ["shoulder_pan", "gripper"]


def write_arm_bag(path: Path, hz: int, seconds: float, width: int, height: int) -> Path:
    from rclpy.serialization import serialize_message
    from sensor_msgs.msg import Image, JointState

    from joshua_runtime.bags.bag_writer import BagWriter

    writer = BagWriter(path)
    writer.add_topic(LEADER, "sensor_msgs/msg/JointState")
    writer.add_topic(FOLLOWER, "sensor_msgs/msg/JointState")
    writer.add_topic(CAMERA, "sensor_msgs/msg/Image")
    start_ns = time.time_ns()
    for i in range(round(seconds * hz)):
        at_ns = start_ns + i * 1_000_000_000 // hz
        writer.write(LEADER, serialize_message(JointState(name=JOINTS, position=[float(i), 0.5])), at_ns)
        writer.write(FOLLOWER, serialize_message(JointState(name=JOINTS, position=[float(i), 0.25])), at_ns + 1)
        pixels = np.full((height, width, 3), i % 256, dtype=np.uint8)
        image = Image(height=height, width=width, encoding="rgb8", step=width * 3, data=pixels.tobytes())
        writer.write(CAMERA, serialize_message(image), at_ns + 2)
    writer.close()
    return path
