"""Helpers of the AI tests: settings compiled by joshuac, node processes with live output, a ROS peer.

Node settings come from testsupport/compiled_settings.py (the real compiler); the ROS peer is the
client of testsupport/ros_client.py spun by a thread. The NodeProcess here streams each output line
as it comes, because these tests wait for log lines while a node runs (episode saved, ready);
node_process.NodeProcess there reads output at exit.
"""

import json
import os
import re
import subprocess
import sys
import threading
import time

import numpy as np

from testsupport.ros_client import SPIN_SLICE_S, RosClient

LINE_TIMEOUT_S = 90.0
EXIT_TIMEOUT_S = 30.0
ROBOT = "test_arm"
RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
IMAGE = "sensor_msgs/msg/Image"


def topic(name: str, message_type: str, qos: dict = RELIABLE) -> dict:
    """A topic entry of a settings dict (for settings the compiler would never write)."""
    return {"name": name, "message_type": message_type, "qos": dict(qos)}


def _fields(**values) -> str:
    """pbtxt fields: strings quoted, lists bracketed, everything else as is."""
    parts = []
    for key, value in values.items():
        if isinstance(value, (list, tuple)):
            value = "[" + ", ".join(f'"{v}"' if isinstance(v, str) else str(v) for v in value) + "]"
        elif isinstance(value, str) and not value.isupper():
            value = f'"{value}"'
        parts.append(f"{key}: {value}")
    return " ".join(parts)


def node_block(name: str, node_type: str, **fields) -> str:
    """One `node { }` block of a description."""
    return f'  node {{ name: "{name}" type: {node_type} {_fields(**fields)} }}\n'


def mock_camera(name: str, topic_name: str, width: int, height: int, rate_hz: float) -> str:
    return node_block(name, "MOCK_CAMERA_PUBLISHER", topic_name=topic_name, width=width, height=height, rate_hz=rate_hz)


def mock_encoder(name: str, topic_name: str, joints: list[str], rate_hz: float) -> str:
    ids = list(range(1, len(joints) + 1))
    return node_block(
        name, "MOCK_ENCODER_PUBLISHER", topic_name=topic_name, joint_names=joints, device_ids=ids, rate_hz=rate_hz
    )


def compiled(mode: str, *nodes: str) -> dict[str, dict]:
    """Every node's settings, written by joshuac from a description of these nodes."""
    from testsupport.compiled_settings import compiled_settings

    return compiled_settings(f'robot_config {{\n  name: "{ROBOT}"\n  mode: {mode}\n{"".join(nodes)}}}\n')


class NodeProcess:
    """A node run the way a generated entrypoint runs it, stdout and stderr collected line by line; on this
    machine, or inside `host` (a simulated computer of testsupport/hosts.py)."""

    def __init__(self, settings: dict, env: dict, host=None):
        code = f"from joshua_runtime.entrypoint import run_node; import sys; sys.exit(run_node({settings!r}))"
        command = [sys.executable, "-c", code]
        self.process = subprocess.Popen(
            host.command(command) if host is not None else command,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
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


class RosPeer(RosClient):
    """A RosClient spun by a thread of its own, so that its timers publish synthetic sensors while a test
    waits on a node's output; its waits only watch."""

    def __init__(self, name: str = "test_peer"):
        super().__init__(name)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)

    def spin_until(self, condition, timeout_s: float, every=None) -> bool:
        """Wait until `condition()` holds (the thread spins), calling `every()` each slice; whether it held."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if every is not None:
                every()
            time.sleep(SPIN_SLICE_S)
            if condition():
                return True
        return False

    def send_text(self, publisher, text: str, timeout_s: float = LINE_TIMEOUT_S) -> None:
        """Publish a std_msgs/String once a subscriber has matched (a volatile message sent earlier is lost)."""
        from std_msgs.msg import String

        matched = self.spin_until(lambda: publisher.get_subscription_count() > 0, timeout_s)
        assert matched, f"no subscriber of {publisher.topic_name} within {timeout_s} s"
        publisher.publish(String(data=text))

    def publish_periodically(self, topic_name: str, message_class, rate_hz: float, make_message):
        """Publish `make_message()` on a topic at `rate_hz` until `close()`; returns the timer."""
        publisher = self.publisher(topic_name, message_class, RELIABLE)
        return self.node.create_timer(1.0 / rate_hz, lambda: publisher.publish(make_message()))

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        super().close()


def pattern_image(height: int, width: int, level: int) -> np.ndarray:
    """A deterministic RGB test image: a horizontal ramp plus a per-call level."""
    ramp = (np.arange(width, dtype=np.uint16) * 255 // max(1, width - 1)).astype(np.uint8)
    image = np.empty((height, width, 3), np.uint8)
    image[:, :, 0] = ramp
    image[:, :, 1] = level
    image[:, :, 2] = 255 - ramp
    return image


def save_tiny_diffusion(directory, height: int, width: int, action_min: np.ndarray, action_max: np.ndarray):
    """A small untrained Diffusion policy saved with its processors, as LeRobot saves any policy."""
    import torch
    from lerobot.configs.types import FeatureType, PolicyFeature
    from lerobot.policies.diffusion.configuration_diffusion import DiffusionConfig
    from lerobot.policies.diffusion.modeling_diffusion import DiffusionPolicy
    from lerobot.policies.factory import make_pre_post_processors

    config = DiffusionConfig(
        device="cpu",
        push_to_hub=False,
        n_obs_steps=2,
        horizon=8,
        n_action_steps=2,
        drop_n_last_frames=5,
        down_dims=(16, 32),
        n_groups=4,
        diffusion_step_embed_dim=16,
        spatial_softmax_num_keypoints=8,
        num_inference_steps=2,
        input_features={
            "observation.images.camera": PolicyFeature(FeatureType.VISUAL, (3, height, width)),
            "observation.state": PolicyFeature(FeatureType.STATE, (2,)),
        },
        output_features={"action": PolicyFeature(FeatureType.ACTION, (2,))},
    )

    def stats(low, high, shape):
        low, high = torch.tensor(low, dtype=torch.float32), torch.tensor(high, dtype=torch.float32)
        return {
            "min": low.reshape(shape),
            "max": high.reshape(shape),
            "mean": ((low + high) / 2).reshape(shape),
            "std": ((high - low) / 4).reshape(shape),
        }

    dataset_stats = {
        "observation.images.camera": stats([0.0] * 3, [1.0] * 3, (3, 1, 1)),
        "observation.state": stats([-2.0, -2.0], [2.0, 2.0], (2,)),
        "action": stats(action_min.tolist(), action_max.tolist(), (2,)),
    }
    torch.manual_seed(0)
    policy = DiffusionPolicy(config)
    preprocessor, postprocessor = make_pre_post_processors(config, dataset_stats=dataset_stats)
    policy.save_pretrained(directory)
    preprocessor.save_pretrained(directory)
    postprocessor.save_pretrained(directory)
    # What `joshua-registry import` keeps from the training dataset: the action names.
    (directory / "joshua_features.json").write_text(json.dumps({"action": ["wrist.pos", "gripper.pos"]}))
    return directory


# A sitecustomize: the interpreter sleeps {starting} s as it starts, and any import of lerobot sleeps {lerobot} s first.
SLOW_START_HOOK = """
import sys, time

time.sleep({starting})


class SlowLeRobot:
    def find_spec(self, name, path=None, target=None):
        if name == "lerobot":
            time.sleep({lerobot})
        return None


sys.meta_path.insert(0, SlowLeRobot())
"""


def slow_lerobot_env(tmp_path, env: dict, seconds: float, starting_s: float = 0.0) -> dict:
    """`env` with a sitecustomize on PYTHONPATH that makes any import of lerobot sleep `seconds` first, and each
    Python process sleep `starting_s` as its interpreter starts (before any code of its own runs)."""
    hooks = tmp_path / "hooks"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(SLOW_START_HOOK.format(starting=starting_s, lerobot=seconds))
    return dict(env, PYTHONPATH=os.pathsep.join(filter(None, [str(hooks), env.get("PYTHONPATH")])))
