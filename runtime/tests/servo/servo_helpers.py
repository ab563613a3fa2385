"""Helpers of the servo tests: node settings shaped like a generated entrypoint's, node processes, polling."""

import signal
import subprocess
import sys
import time

SO100_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
SO100_IDS = [1, 2, 3, 4, 5, 6]
RELIABLE_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
JOINT_STATE = "sensor_msgs/msg/JointState"
NODE_STOP_TIMEOUT_S = 5.0
WAIT_POLL_S = 0.02


def topic(name: str, qos: dict | None = None) -> dict:
    return {"name": name, "message_type": JOINT_STATE, "qos": dict(qos or RELIABLE_QOS)}


def node_settings(node_type: str, name: str, serial_port, topic_name: str, **overrides) -> dict:
    """A settings dict shaped exactly as entrypoint.py documents, for one servo node."""
    settings = {
        "robot": "so100_test",
        "mode": "MODE_TELEOPERATION",
        "name": name,
        "type": node_type,
        "topic": topic(topic_name),
        "state_topic": None,
        "inputs": [],
        "qos": dict(RELIABLE_QOS),
        "serial_port": str(serial_port),
        "baud_rate": 1_000_000,
        "device_ids": list(SO100_IDS),
        "joint_names": list(SO100_JOINTS),
        "calibration_file": "",
        "camera_index": 0,
        "video_source": "",
        "width": 0,
        "height": 0,
        "rate_hz": 100.0,
        "frame_id": "base_link",
        "model_path": "",
        "policy_type": "",
        "device": "",
        "output_format": "",
        "output_directory": "",
        "simulation": None,
    }
    settings.update(overrides)
    return settings


class NodeProcess:
    """A node run as `python -c "...run_node(SETTINGS)"`, the way a generated entrypoint runs it."""

    def __init__(self, settings: dict, env: dict):
        code = (
            "import sys\nfrom joshua_runtime.entrypoint import run_node\n"
            f"sys.exit(run_node({settings!r}))\n"
        )
        self.process = subprocess.Popen(
            [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )

    def stop(self, signum=signal.SIGINT) -> tuple[int, float, str]:
        """Send `signum`; return (exit code, seconds until exit, stderr)."""
        started = time.monotonic()
        if self.process.poll() is None:
            self.process.send_signal(signum)
        try:
            _, stderr = self.process.communicate(timeout=NODE_STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            _, stderr = self.process.communicate()
        return self.process.returncode, time.monotonic() - started, stderr

    def failure(self) -> str:
        """Why the process is gone (exit code and stderr), or that it still runs."""
        if self.process.poll() is None:
            return "process still running"
        return f"exit code {self.process.returncode}: {self.process.communicate()[1]}"

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.communicate()


def wait_for(predicate, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(WAIT_POLL_S)
    return bool(predicate())


def assert_pid_alive(node: NodeProcess) -> None:
    assert node.process.poll() is None, node.process.communicate()[1]


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
