"""ACT inference on CPU: select_action latency p50/p99 and the INFERENCE node's start-to-first-action time.

    .venv/bin/python bench/inference.py [--calls 30] [--height 480 --width 640] [--starts 2] [--quick]

An ACT policy with LeRobot's default architecture (ResNet-18 backbone without downloaded weights,
dim_model 512, 4 encoder layers, chunk 100), one camera and a 6-joint state, is saved with its
processors and loaded with the node's own loader (`PolicyRunner`). Latency is measured on the
node's whole inference path (LeRobot's predict_action: preprocessing, select_action,
postprocessing): once with n_action_steps=1 (the model runs at every call) and once with the
default n_action_steps=100 (99 of 100 calls pop a queued action). Then an INFERENCE node process
is started on the same policy while this process publishes the camera and joint state; the times
from process start to "ready" and to the first action received are reported. Most of it is
importing torch and LeRobot: where the environment has no compiled bytecode and forbids writing
it (PYTHONDONTWRITEBYTECODE), every start compiles them from source, which adds 10-20 s.
--quick: the smallest ACT that still runs the same path (64x48 camera, dim_model 64, one encoder and
one decoder layer, chunks of 10), a few calls and one node start.
"""

import argparse
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
from support.described_nodes import compiled_settings, node_command, topic_qos, write_fastdds_profiles
from support.ros_env import bench_environment

from joshua_core import so100

JOINTS = list(so100.SO100_JOINTS)
# Only the policy node runs: this process publishes in place of the camera and the follower arm,
# with their topics and QoS (the camera reliable, as the policy's image input has always been
# published here). The policy directory and the image size are set per run (`--set`).
DESCRIPTION = """
robot_config {
  name: "bench"
  mode: MODE_INFERENCE
  node {
    name: "camera"
    type: MOCK_CAMERA_PUBLISHER
    topic_name: "/camera/image_raw"
    qos_reliability: RELIABLE
    qos_depth: 10
  }
  node { name: "follower" type: MOCK_ENCODER_PUBLISHER topic_name: "/follower/joint_states" }
  node {
    name: "policy"
    type: INFERENCE
    topic_name: "/arm/commands"
    input_topics: ["/camera/image_raw", "/follower/joint_states"]
    policy_type: "act"
  }
}
"""
POLICY = "policy"
WARMUP_CALLS = 3
CHUNKED_CALLS = 200
CHUNK_SIZE = 100  # ACT's default
QUICK_ACT = {
    "dim_model": 64,
    "dim_feedforward": 128,
    "n_encoder_layers": 1,
    "n_decoder_layers": 1,
    "latent_dim": 8,
    "chunk_size": 10,
}
QUICK_CALLS, QUICK_HEIGHT, QUICK_WIDTH = 3, 48, 64
PUBLISH_HZ = 30.0
FIRST_ACTION_TIMEOUT_S = 300.0
STOP_TIMEOUT_S = 10.0


def save_act(directory: Path, height: int, width: int, n_action_steps: int, architecture: dict) -> Path:
    import torch
    from lerobot.configs.types import FeatureType, PolicyFeature
    from lerobot.policies.act.configuration_act import ACTConfig
    from lerobot.policies.act.modeling_act import ACTPolicy
    from lerobot.policies.factory import make_pre_post_processors

    config = ACTConfig(
        device="cpu",
        push_to_hub=False,
        pretrained_backbone_weights=None,
        n_action_steps=n_action_steps,
        **architecture,
        input_features={
            "observation.images.camera": PolicyFeature(FeatureType.VISUAL, (3, height, width)),
            "observation.state": PolicyFeature(FeatureType.STATE, (len(JOINTS),)),
        },
        output_features={"action": PolicyFeature(FeatureType.ACTION, (len(JOINTS),))},
    )
    ones = torch.ones(len(JOINTS))
    stats = {
        "observation.images.camera": {"mean": torch.full((3, 1, 1), 0.5), "std": torch.full((3, 1, 1), 0.25)},
        "observation.state": {"mean": 0 * ones, "std": ones},
        "action": {"mean": 0 * ones, "std": ones},
    }
    torch.manual_seed(0)
    policy = ACTPolicy(config)
    preprocessor, postprocessor = make_pre_post_processors(config, dataset_stats=stats)
    policy.save_pretrained(directory)
    preprocessor.save_pretrained(directory)
    postprocessor.save_pretrained(directory)
    (directory / "joshua_features.json").write_text(json.dumps({"action": [j + ".pos" for j in JOINTS]}))
    return directory


def observation(height: int, width: int) -> dict:
    rng = np.random.default_rng(0)
    return {
        "observation.images.camera": rng.integers(0, 256, (height, width, 3), dtype=np.uint8),
        "observation.state": rng.normal(size=len(JOINTS)).astype(np.float32),
    }


def latency_ms(policy_dir: Path, obs: dict, calls: int) -> list[float]:
    from joshua_runtime.ai.policy_runner import PolicyRunner

    runner = PolicyRunner(policy_dir, "cpu")
    for _ in range(WARMUP_CALLS):
        runner.act(obs)
    runner.reset()
    samples = []
    for _ in range(calls):
        start = time.perf_counter()
        runner.act(obs)
        samples.append((time.perf_counter() - start) * 1000)
    return samples


def percentile(samples: list[float], fraction: float) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, int(round(fraction * (len(ordered) - 1))))]


def overrides(policy_dir: Path, height: int, width: int) -> list[str]:
    return [f"{POLICY}.model_path={policy_dir}", f"camera.height={height}", f"camera.width={width}"]


def start_to_first_action(settings: dict[str, dict], obs: dict, env: dict) -> tuple[float, float]:
    """Seconds from process start to 'ready' and to the first action received, publishing `obs`."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from sensor_msgs.msg import Image, JointState

    from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("bench_inference_peer", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    image = rgb_to_image(obs["observation.images.camera"])
    state = joint_state(JOINTS, obs["observation.state"])
    camera, follower, actions = settings["camera"]["topic"], settings["follower"]["topic"], settings[POLICY]["topic"]
    images = node.create_publisher(Image, camera["name"], topic_qos(camera))
    states = node.create_publisher(JointState, follower["name"], topic_qos(follower))
    node.create_timer(1 / PUBLISH_HZ, lambda: (images.publish(image), states.publish(state)))
    first = threading.Event()
    node.create_subscription(JointState, actions["name"], lambda _msg: first.set(), topic_qos(actions))
    started = time.monotonic()
    process = subprocess.Popen(
        node_command(settings[POLICY]), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    lines: list[str] = []
    ready_at: list[float] = []

    def read():
        for line in process.stdout:
            lines.append(line)
            if not ready_at and re.search(r"\bready: ", line):
                ready_at.append(time.monotonic() - started)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        while not first.is_set():
            executor.spin_once(timeout_sec=0.01)
            if time.monotonic() - started > FIRST_ACTION_TIMEOUT_S or process.poll() is not None:
                raise RuntimeError("no action received:\n" + "".join(lines))
        first_action_s = time.monotonic() - started
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        executor.shutdown(timeout_sec=0)
        node.destroy_node()
        context.try_shutdown()
    return (ready_at[0] if ready_at else float("nan")), first_action_s


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=30, help="timed calls that run the model")
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--starts", type=int, default=2, help="node starts measured")
    parser.add_argument("--quick", action="store_true", help="the smallest ACT, a few calls, one start (for the tests)")
    args = parser.parse_args()
    architecture, chunk, chunked_calls = {}, CHUNK_SIZE, CHUNKED_CALLS
    if args.quick:
        args.calls, args.height, args.width, args.starts = QUICK_CALLS, QUICK_HEIGHT, QUICK_WIDTH, 1
        architecture, chunk = QUICK_ACT, QUICK_ACT["chunk_size"]
        chunked_calls = 2 * chunk
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    with tempfile.TemporaryDirectory(prefix="joshua-bench-inference-") as tmp:
        workdir = Path(tmp)
        every_call_dir = workdir / "act_every_call"
        described = overrides(every_call_dir, args.height, args.width)
        settings = compiled_settings(DESCRIPTION, described, "bench_inference.pbtxt")
        obs = observation(args.height, args.width)
        print(
            f"ACT ({'quick' if args.quick else 'default'} architecture), 1 camera {args.width}x{args.height}, "
            f"{len(JOINTS)}-joint state, CPU, torch threads {__import__('torch').get_num_threads()}"
        )
        every_call = save_act(every_call_dir, args.height, args.width, 1, architecture)
        chunked = save_act(workdir / "act_chunked", args.height, args.width, chunk, architecture)
        for label, policy_dir, calls in (
            ("model at every call", every_call, args.calls),
            (f"chunk of {chunk} actions", chunked, chunked_calls),
        ):
            samples = latency_ms(policy_dir, obs, calls)
            print(
                f"select_action ({label:<20}) calls {calls:>4}  p50 {percentile(samples, 0.5):8.2f} ms  "
                f"p99 {percentile(samples, 0.99):8.2f} ms  max {max(samples):8.2f} ms"
            )
        profiles = write_fastdds_profiles(DESCRIPTION, workdir, described, "bench_inference.pbtxt")
        # This process publishes the camera's images, so it loads the policy node's profile too.
        env = bench_environment("inference", FASTRTPS_DEFAULT_PROFILES_FILE=str(profiles[POLICY]))
        os.environ.update(env)
        for start in range(1, args.starts + 1):
            ready_s, first_s = start_to_first_action(settings, obs, env)
            print(f"INFERENCE node start {start}: ready after {ready_s:6.2f} s, first action after {first_s:6.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
