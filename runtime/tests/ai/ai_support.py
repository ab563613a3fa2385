"""Helpers of the AI tests: node settings, node processes, and an in-process ROS peer."""

import re
import subprocess
import sys
import threading
import time
from collections import deque

import numpy as np

LINE_TIMEOUT_S = 90.0
EXIT_TIMEOUT_S = 30.0
RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
JOINT_STATE = "sensor_msgs/msg/JointState"
IMAGE = "sensor_msgs/msg/Image"


def topic(name: str, message_type: str, qos: dict = RELIABLE) -> dict:
    return {"name": name, "message_type": message_type, "qos": dict(qos)}


def node_settings(name: str, node_type: str, **overrides) -> dict:
    """A settings dict shaped exactly as documented in joshua_runtime/entrypoint.py."""
    settings = {
        "robot": "test_arm", "mode": "MODE_DATA_COLLECTION", "name": name, "type": node_type,
        "topic": None, "state_topic": None, "inputs": [], "qos": dict(RELIABLE),
        "serial_port": "", "baud_rate": 0, "device_ids": [], "joint_names": [], "calibration_file": "",
        "camera_index": -1, "video_source": "", "width": 640, "height": 480, "rate_hz": 10.0,
        "frame_id": "base_link", "model_path": "", "policy_type": "", "device": "cpu",
        "output_format": "lerobot", "output_directory": "", "simulation": None,
    }
    unknown = set(overrides) - set(settings)
    assert not unknown, f"not a settings key: {unknown}"
    settings.update(overrides)
    return settings


class NodeProcess:
    """A node run the way a generated entrypoint runs it, with its output collected line by line."""

    def __init__(self, settings: dict, env: dict):
        code = (
            "from joshua_runtime.entrypoint import run_node; import sys; "
            f"sys.exit(run_node({settings!r}))"
        )
        self.process = subprocess.Popen(
            [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )
        self.lines: list[str] = []
        self._condition = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.process.stdout:
            with self._condition:
                self.lines.append(line.rstrip("\n"))
                self._condition.notify_all()
        with self._condition:
            self._condition.notify_all()

    def wait_for(self, pattern: str, after: int = 0, timeout: float = LINE_TIMEOUT_S) -> re.Match:
        """The first match of `pattern` in the output lines from index `after` on."""
        regex = re.compile(pattern)
        deadline = time.monotonic() + timeout
        with self._condition:
            while True:
                for line in self.lines[after:]:
                    found = regex.search(line)
                    if found:
                        return found
                if self.process.poll() is not None and not self._reader.is_alive():
                    raise AssertionError(f"exited ({self.process.returncode}) before {pattern!r}:\n{self.output}")
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError(f"no {pattern!r} within {timeout} s:\n{self.output}")
                self._condition.wait(min(remaining, 0.5))

    def count(self) -> int:
        with self._condition:
            return len(self.lines)

    @property
    def output(self) -> str:
        with self._condition:
            return "\n".join(line for line in self.lines if not line.startswith("Svt["))

    def stop(self, signal_number: int, timeout: float = EXIT_TIMEOUT_S) -> int:
        self.process.send_signal(signal_number)
        code = self.process.wait(timeout)
        self._reader.join(timeout)
        return code

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


class RosPeer:
    """An in-process rclpy node that publishes synthetic sensors and collects messages."""

    def __init__(self, name: str = "test_peer"):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node(name, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.received: dict[str, deque] = {}
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def publisher(self, name: str, message_type: str):
        from joshua_runtime.messages import message_class
        from joshua_runtime.qos import qos_profile

        return self.node.create_publisher(message_class(message_type), name, qos_profile(RELIABLE))

    def send_text(self, publisher, text: str, timeout: float = LINE_TIMEOUT_S) -> None:
        """Publish a std_msgs/String once a subscriber has matched (a volatile message sent earlier is lost)."""
        from std_msgs.msg import String

        wait_until(lambda: publisher.get_subscription_count() > 0, timeout, f"a subscriber of {publisher.topic_name}")
        publisher.publish(String(data=text))

    def publish_periodically(self, name: str, message_type: str, rate_hz: float, make_message):
        """Publish `make_message()` on a topic at `rate_hz` until `close()`; returns the timer."""
        publisher = self.publisher(name, message_type)
        return self.node.create_timer(1.0 / rate_hz, lambda: publisher.publish(make_message()))

    def collect(self, name: str, message_type: str) -> deque:
        from joshua_runtime.messages import message_class
        from joshua_runtime.qos import qos_profile

        box = self.received.setdefault(name, deque())
        self.node.create_subscription(
            message_class(message_type), name, lambda message: box.append(message), qos_profile(RELIABLE))
        return box

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        self.context.try_shutdown()


def wait_until(predicate, timeout: float = LINE_TIMEOUT_S, what: str = "condition") -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def pattern_image(height: int, width: int, level: int) -> np.ndarray:
    """A deterministic RGB test image: a horizontal ramp plus a per-call level."""
    ramp = (np.arange(width, dtype=np.uint16) * 255 // max(1, width - 1)).astype(np.uint8)
    image = np.empty((height, width, 3), np.uint8)
    image[:, :, 0] = ramp
    image[:, :, 1] = level
    image[:, :, 2] = 255 - ramp
    return image
