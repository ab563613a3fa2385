"""Helpers of the sensor tests: node settings, node processes and an in-process rclpy client."""

import subprocess
import sys
import time

NODE_START_TIMEOUT_S = 30.0  # a cold rclpy process on a busy 2-core machine
MESSAGE_TIMEOUT_S = 15.0
DISCOVERY_POLL_S = 0.05
SHUTDOWN_CONTRACT_S = 0.5  # every node exits within this after SIGINT/SIGTERM (DESIGN.md)
KILL_TIMEOUT_S = 5.0
# What the graph reports for an endpoint whose node announcement has not arrived yet.
UNKNOWN_NODE_NAME = "_NODE_NAME_UNKNOWN_"

SENSOR_QOS = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}
DEFAULT_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
SO100_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]


def node_settings(node_type: str, name: str, topic: str, message_type: str, qos: dict, **fields) -> dict:
    """A settings dict shaped exactly as entrypoint.py documents, with the fields given overridden."""
    settings = {
        "robot": "testbot",
        "mode": "MODE_TELEOPERATION",
        "name": name,
        "type": node_type,
        "topic": {"name": topic, "message_type": message_type, "qos": qos},
        "state_topic": None,
        "inputs": [],
        "qos": qos,
        "serial_port": "",
        "baud_rate": 0,
        "device_ids": [],
        "joint_names": [],
        "calibration_file": "",
        "camera_index": -1,
        "video_source": "",
        "width": 640,
        "height": 480,
        "rate_hz": 30.0,
        "frame_id": "base_link",
        "model_path": "",
        "policy_type": "",
        "device": "cpu",
        "output_format": "lerobot",
        "output_directory": "",
        "simulation": None,
    }
    unknown = set(fields) - set(settings)
    assert not unknown, f"not a settings key: {unknown}"
    settings.update(fields)
    return settings


class NodeProcess:
    """One node run as `python -c "...run_node(SETTINGS)"` in its own process."""

    def __init__(self, settings: dict, env: dict):
        code = ("import sys; from joshua_runtime.entrypoint import run_node; "
                f"sys.exit(run_node({settings!r}))")
        self.process = subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)

    def stop(self, signum: int) -> tuple[int, float]:
        """Send `signum`; return (exit code, seconds until the process ended)."""
        sent = time.monotonic()
        self.process.send_signal(signum)
        code = self.process.wait(KILL_TIMEOUT_S)
        return code, time.monotonic() - sent

    def wait(self, timeout: float = NODE_START_TIMEOUT_S) -> tuple[int, str]:
        """Wait for the process to end by itself; return (exit code, stderr)."""
        _, stderr = self.process.communicate(timeout=timeout)
        return self.process.returncode, stderr

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(KILL_TIMEOUT_S)
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()


class RosClient:
    """An in-process rclpy node with helpers to inspect the graph and collect messages."""

    def __init__(self, context):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.node = rclpy.create_node("sensors_test_client", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)

    def spin_for(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)

    def publishers(self, topic: str, timeout: float = NODE_START_TIMEOUT_S, process: NodeProcess | None = None):
        """The publisher endpoints of `topic` once there is one."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            infos = self.node.get_publishers_info_by_topic(topic)
            if infos and all(info.node_name != UNKNOWN_NODE_NAME for info in infos):
                return infos
            if process is not None and process.process.poll() is not None:
                raise AssertionError(f"node exited with {process.process.returncode}: {process.wait()[1]}")
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        raise AssertionError(f"no publisher on {topic} within {timeout} s")

    def subscribers(self, topic: str, timeout: float = NODE_START_TIMEOUT_S):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            infos = self.node.get_subscriptions_info_by_topic(topic)
            if infos and all(info.node_name != UNKNOWN_NODE_NAME for info in infos):
                return infos
            self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        raise AssertionError(f"no subscription on {topic} within {timeout} s")

    def collect(self, message_class, topic: str, qos: dict, count: int, timeout: float = MESSAGE_TIMEOUT_S) -> list:
        """The first `count` messages received on `topic` with a subscription of `qos`."""
        from joshua_runtime.qos import qos_profile

        received = []
        subscription = self.node.create_subscription(message_class, topic, received.append, qos_profile(qos))
        try:
            deadline = time.monotonic() + timeout
            while len(received) < count and time.monotonic() < deadline:
                self.executor.spin_once(timeout_sec=DISCOVERY_POLL_S)
        finally:
            self.node.destroy_subscription(subscription)
        assert len(received) >= count, f"{len(received)} of {count} messages on {topic} within {timeout} s"
        return received[:count]
