"""Helpers of the servo tests: the SO-100 bus layout, polling, and an in-process rclpy client.

Node settings come from the compiler (testsupport/compiled_settings.py) and node
processes from testsupport/node_process.py.
"""

import time

SO100_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
SO100_IDS = [1, 2, 3, 4, 5, 6]
WAIT_POLL_S = 0.02


def wait_for(predicate, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(WAIT_POLL_S)
    return bool(predicate())


SPIN_SLICE_S = 0.02


class RosProbe:
    """An in-process rclpy node (own context) that keeps the messages received on each topic."""

    def __init__(self):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self._rclpy = rclpy
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("servo_probe", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.received: dict[str, list] = {}

    def listen(self, topic_name: str, message_type, qos) -> None:
        self.received[topic_name] = []
        self.node.create_subscription(message_type, topic_name, self.received[topic_name].append, qos)

    def last(self, topic_name: str):
        messages = self.received.get(topic_name)
        return messages[-1] if messages else None

    def spin_until(self, condition, timeout_s: float, every=None) -> bool:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if every is not None:
                every()
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)
            if condition():
                return True
        return False

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        self._rclpy.shutdown(context=self.context)
