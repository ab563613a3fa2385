"""Helpers of the process tests: QoS profiles and an rclpy client (node processes: start_node, root conftest)."""

import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

STARTUP_TIMEOUT_S = 30.0
SPIN_SLICE_S = 0.05

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
SENSOR = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)


class Client:
    """An rclpy node in this process that records the last message of each topic."""

    def __init__(self):
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("sim_probe", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.last = {}

    def listen(self, topic: str, message_type, qos: QoSProfile) -> None:
        self.node.create_subscription(message_type, topic, lambda msg: self.last.__setitem__(topic, msg), qos)

    def spin_until(self, condition, timeout_s: float, every=None) -> bool:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if every:
                every()
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)
            if condition():
                return True
        return False

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)
