"""Helpers of the process tests: start a node the way a generated entrypoint does, and an rclpy client."""

import signal
import subprocess
import sys
import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

STARTUP_TIMEOUT_S = 30.0
EXIT_TIMEOUT_S = 5.0
SPIN_SLICE_S = 0.05

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
SENSOR = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)


def start_node(settings: dict, env: dict) -> subprocess.Popen:
    code = f"from joshua_runtime.entrypoint import run_node; import sys; sys.exit(run_node({settings!r}))"
    return subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def stop_node(process: subprocess.Popen, signum=signal.SIGINT) -> tuple[int, str, float]:
    """Send `signum`; return the exit code, stderr and seconds taken to exit."""
    sent = time.monotonic()
    process.send_signal(signum)
    try:
        _, stderr = process.communicate(timeout=EXIT_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        _, stderr = process.communicate()
    return process.returncode, stderr, time.monotonic() - sent


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
