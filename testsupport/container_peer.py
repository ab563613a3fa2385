"""A ROS 2 peer for a robot running in a container: records JointState topics for a while and prints them as JSON.

    python3 container_peer.py --seconds S --timeout T TOPIC...

It runs with the image's own Python (rclpy comes with the robot's environment), in a second
container beside the robot's: the same network namespace, and the robot's IPC namespace, whose
/dev/shm Fast DDS uses between processes of one machine. It waits up to T seconds for a first
message on every topic, then records S seconds more, and prints {"TOPIC": [{"t": receipt time,
"stamp": the header's stamp in seconds, "name": [...], "position": [...], "velocity": [...],
"effort": [...]}, ...]}; exit code 3 when a topic stayed silent.
"""

import argparse
import json
import sys
import time

SPIN_S = 0.05
EXIT_SILENT = 3


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("topics", nargs="+")
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--timeout", type=float, default=30.0)
    args = parser.parse_args()

    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    rclpy.init()
    node = rclpy.create_node("container_peer")
    samples = {topic: [] for topic in args.topics}

    def record(topic):
        def received(message):
            samples[topic].append(
                {
                    "t": time.monotonic(),
                    "stamp": message.header.stamp.sec + message.header.stamp.nanosec * 1e-9,
                    "name": list(message.name),
                    "position": list(message.position),
                    "velocity": list(message.velocity),
                    "effort": list(message.effort),
                }
            )

        return received

    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
    for topic in args.topics:
        node.create_subscription(JointState, topic, record(topic), qos)
    deadline = time.monotonic() + args.timeout
    while not all(samples.values()) and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=SPIN_S)
    if all(samples.values()):
        end = time.monotonic() + args.seconds
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=SPIN_S)
    print(json.dumps(samples))
    node.destroy_node()
    rclpy.shutdown()
    return 0 if all(samples.values()) else EXIT_SILENT


if __name__ == "__main__":
    sys.exit(main())
