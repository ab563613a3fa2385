"""The robot side of bench/remote_inference.py, a process of its own so it can run on another (simulated) host.

    python -m support.chunk_peer SPEC_JSON          (from bench/)

SPEC_JSON names the camera, state and action topics (compiled settings), the action type (JointState:
every message is a command; JointTrajectory: chunks followed with the actuators' own rule at CONTROL_HZ),
the image message (raw Image or JPEG CompressedImage, as camera nodes send it), the measurement and
warm-up seconds and the model calls to measure at least ("min_calls": the measurement goes on past its
seconds until that many came). It publishes tiny_act's picture and arm pose at POLICY_HZ, waits for the
first command, lets WARM_UP pass, measures, and prints one JSON line: {"commands", "seconds", "latencies_s"} (or
{"error"} when no command came). "latency": from an observation's header stamp to the first command
executed from the model call on it.
"""

import json
import sys
import threading
import time

import cv2

from support.described_nodes import topic_qos
from testsupport import tiny_act

CONTROL_HZ = 30.0
POLICY_HZ = 30
JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
COMPRESSED = "sensor_msgs/msg/CompressedImage"
SPIN_SLICE_S = 0.05
POLL_S = 0.05


class Peer:
    """Publishes the camera and arm state, and is the actuator: counts commands and their latency."""

    def __init__(self, spec: dict):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("bench_chunk_peer", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.commands: list[float] = []
        self.latencies_s: list[float] = []
        self._publish_observations(spec["camera"], spec["state"])
        action = spec["action"]
        (self._follow_chunks if action["message_type"] == JOINT_TRAJECTORY else self._follow_states)(action)
        self._stop = threading.Event()
        self._spinner = threading.Thread(target=self._spin, daemon=True)
        self._spinner.start()

    def _publish_observations(self, camera: dict, state: dict) -> None:
        from sensor_msgs.msg import CompressedImage, Image, JointState

        from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image
        from joshua_runtime.convert.image import JPEG_QUALITY

        compressed = camera["message_type"] == COMPRESSED
        images = self.node.create_publisher(CompressedImage if compressed else Image, camera["name"], topic_qos(camera))
        states = self.node.create_publisher(JointState, state["name"], topic_qos(state))
        started = time.monotonic()

        def image(pixels, stamp):
            if not compressed:
                return rgb_to_image(pixels, stamp)
            bgr = cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR)
            message = CompressedImage(
                format="jpeg", data=cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])[1].tobytes()
            )
            message.header.stamp = stamp
            return message

        def publish() -> None:
            t, stamp = time.monotonic() - started, self.node.get_clock().now().to_msg()
            images.publish(image(tiny_act.frame_image(t), stamp))
            states.publish(joint_state(tiny_act.JOINTS, tiny_act.pose(t), stamp))

        self.node.create_timer(1.0 / POLICY_HZ, publish)

    def _spin(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)

    def now_s(self) -> float:
        return self.node.get_clock().now().nanoseconds / 1e9

    def _follow_states(self, topic: dict) -> None:
        """Every JointState is a command; its latency is its age (stamped with the observation's time)."""
        from sensor_msgs.msg import JointState

        from joshua_runtime.ai.ros_arrays import stamp_seconds

        def receive(message) -> None:
            now = self.now_s()
            self.commands.append(now)
            self.latencies_s.append(now - stamp_seconds(message))

        self.node.create_subscription(JointState, topic["name"], receive, topic_qos(topic))

    def _follow_chunks(self, topic: dict) -> None:
        """The actuators' chunk rule at CONTROL_HZ; a chunk's latency is its first executed command."""
        from trajectory_msgs.msg import JointTrajectory

        from joshua_runtime.nodes.trajectory_follower import TrajectoryFollower, chunk_from_trajectory

        rule = TrajectoryFollower(len(tiny_act.JOINTS))
        waiting: list[float] = []  # stamp of the chunk accepted last, not yet executed

        def receive(message) -> None:
            now = self.now_s()
            chunk = chunk_from_trajectory(message, tiny_act.JOINTS, now)
            if rule.accept(chunk, now) == "":
                waiting[:] = [chunk.stamp_s]

        def tick() -> None:
            now = self.now_s()
            if rule.executing(now):
                self.commands.append(now)
                if waiting:
                    self.latencies_s.append(now - waiting.pop())

        self.node.create_subscription(JointTrajectory, topic["name"], receive, topic_qos(topic))
        self.node.create_timer(1.0 / CONTROL_HZ, tick)

    def measure(self, seconds: float, warm_up_s: float, first_command_timeout_s: float, min_calls: int = 0) -> dict:
        deadline = time.monotonic() + first_command_timeout_s
        while not self.commands:
            if time.monotonic() > deadline:
                return {"error": f"no command within {first_command_timeout_s:g} s"}
            time.sleep(POLL_S)
        time.sleep(warm_up_s)
        start, first_latency = self.now_s(), len(self.latencies_s)
        time.sleep(seconds)
        deadline = time.monotonic() + first_command_timeout_s
        while len(self.latencies_s) - first_latency < min_calls and time.monotonic() < deadline:
            time.sleep(POLL_S)
        end = self.now_s()
        commands = sum(1 for t in list(self.commands) if start <= t < end)
        return {"commands": commands, "seconds": end - start, "latencies_s": self.latencies_s[first_latency:]}

    def close(self) -> None:
        self._stop.set()
        self._spinner.join()
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        self.context.try_shutdown()


def main() -> int:
    spec = json.loads(sys.argv[1])
    peer = Peer(spec)
    try:
        result = peer.measure(
            spec["seconds"], spec["warm_up_s"], spec["first_command_timeout_s"], spec.get("min_calls", 0)
        )
    finally:
        peer.close()
    print(json.dumps(result), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
