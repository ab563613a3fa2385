"""The follower of the chunked-inference tests: the actuators' chunk rule at a control rate, with a record of what it did.

In the test process (`ChunkFollower(node, ...)` on a spun rclpy node) or as a process of its own, so it can
run on a simulated computer (testsupport/hosts.py) other than the policy's:

    python runtime/tests/ai/chunk_follower.py SPEC_JSON

SPEC_JSON: {"topic", "joints", "control_hz", "chunks", "timeout_s"}. The process follows chunks until more
than "chunks" arrived (or the timeout passed) and prints one JSON line, the record (`ChunkFollower.record`).
"""

import json
import sys
import time

SPIN_SLICE_S = 0.01  # well under a control period of the tests' rates
RELIABLE_DEPTH = 10


class ChunkFollower:
    """Takes JointTrajectory chunks with nodes/trajectory_follower.py's rule and ticks at `control_hz`."""

    def __init__(self, node, topic: str, joints: list[str], control_hz: float):
        from trajectory_msgs.msg import JointTrajectory

        from joshua_runtime.nodes.trajectory_follower import TrajectoryFollower

        self.node, self.joints = node, list(joints)
        self.rule = TrajectoryFollower(len(joints))
        self.arrivals: list[float] = []  # when each chunk arrived (ROS clock)
        self.commands: list[float] = []  # when each command from a chunk in force was executed
        self.chunks: list[dict] = []  # per chunk: header stamp, joint names, time_from_start of its points
        self.dropped: list[str] = []  # why each chunk was dropped ("" when followed)
        node.create_subscription(JointTrajectory, topic, self.receive, RELIABLE_DEPTH)
        node.create_timer(1.0 / control_hz, self.tick)

    def receive(self, message) -> None:
        from joshua_runtime.nodes.trajectory_follower import chunk_from_trajectory, now_s, ros_seconds

        now = now_s(self.node)
        self.chunks.append(
            {
                "stamp_s": ros_seconds(message.header.stamp),
                "joint_names": list(message.joint_names),
                "steps_s": [ros_seconds(point.time_from_start) for point in message.points],
            }
        )
        self.arrivals.append(now)
        self.dropped.append(self.rule.accept(chunk_from_trajectory(message, self.joints, now), now))

    def tick(self) -> None:
        from joshua_runtime.nodes.trajectory_follower import now_s

        now = now_s(self.node)
        if self.rule.executing(now):
            self.commands.append(now)

    def record(self) -> dict:
        """What happened so far, as plain lists (JSON)."""
        return {
            "arrivals": list(self.arrivals),
            "commands": list(self.commands),
            "chunks": list(self.chunks),
            "dropped": list(self.dropped),
        }


def main() -> int:
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    spec = json.loads(sys.argv[1])
    rclpy.init()
    node = rclpy.create_node("chunk_follower")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    follower = ChunkFollower(node, spec["topic"], spec["joints"], spec["control_hz"])
    deadline = time.monotonic() + spec["timeout_s"]
    try:
        while len(follower.arrivals) <= spec["chunks"] and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=SPIN_SLICE_S)
    finally:
        executor.shutdown(timeout_sec=0)
        node.destroy_node()
        rclpy.try_shutdown()
    print(json.dumps(follower.record()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
