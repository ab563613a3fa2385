"""The subscriber of bench/multihost.py, a process of its own so it can run on another (simulated) host.

    python -m support.joint_state_latency SPEC_JSON          (from bench/)

SPEC_JSON: {"topic": a topic of compiled settings (JointState), "seconds", "first_message_timeout_s"}.
It waits for the first message, then for "seconds" keeps each message's latency: its arrival on the ROS
clock minus its header stamp (the publisher's ROS clock; simulated hosts share the machine's clock). It
prints one JSON line: {"latencies_s": [...]} (or {"error"} when no message came).
"""

import json
import sys
import time

from support.described_nodes import topic_qos

SPIN_SLICE_S = 0.05


def main() -> int:
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from sensor_msgs.msg import JointState

    from joshua_runtime.ai.ros_arrays import stamp_seconds

    spec = json.loads(sys.argv[1])
    rclpy.init()
    node = rclpy.create_node("bench_joint_state_latency")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    latencies_s: list[float] = []
    measuring = [False]

    def receive(message) -> None:
        latency = node.get_clock().now().nanoseconds / 1e9 - stamp_seconds(message)
        if measuring[0]:
            latencies_s.append(latency)
        measuring[0] = True  # from the second message on: the first may have waited for discovery

    node.create_subscription(JointState, spec["topic"]["name"], receive, topic_qos(spec["topic"]))
    deadline = time.monotonic() + spec["first_message_timeout_s"]
    try:
        while not measuring[0] and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=SPIN_SLICE_S)
        end = time.monotonic() + spec["seconds"]
        while measuring[0] and time.monotonic() < end:
            executor.spin_once(timeout_sec=SPIN_SLICE_S)
    finally:
        executor.shutdown(timeout_sec=0)
        node.destroy_node()
        rclpy.try_shutdown()
    if not measuring[0]:
        print(json.dumps({"error": f"no message within {spec['first_message_timeout_s']:g} s"}), flush=True)
    else:
        print(json.dumps({"latencies_s": latencies_s}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
