"""Policies that keep the control rate: commands/s reaching the actuator and observation -> command latency.

    .venv/bin/python bench/remote_inference.py [--seconds 30] [--quick]

One real ACT (testsupport/tiny_act.py: LeRobot's ResNet-18 backbone on a 320x240 camera, chunks of 100
actions at 30 Hz, trained offline for a few steps) and the same data (that module's moving picture and
arm pose, published at 30 Hz), served four ways, side by side:

  (a) sync         today's INFERENCE node with a JointState topic: one model call per published action
  (b) chunked      the INFERENCE node with a JointTrajectory topic: a background thread runs the model
                   while the actuator executes the last chunk
  (c) remote       (b) with the node on another host, images as CompressedImage: `remote_chunked()`
  (d) lerobot      LeRobot's own async inference (policy_server + RobotClient), on 127.0.0.1

The actuator runs at CONTROL_HZ in this process; for (b) it follows chunks with the actuators' own rule
(nodes/trajectory_follower.py). "commands/s": commands executed per second of measurement (a JointState
received; a control tick with a chunk in force; an action LeRobot's client sent to its robot).
"latency": from an observation's time (its header stamp; LeRobot's TimedObservation timestamp) to the
first command the actuator executes from the model call on it, p50 and p99 over the calls measured.
--quick: a few seconds each, for the tests.
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
from support.described_nodes import compiled_settings, node_command, topic_qos
from support.ros_env import bench_environment

from testsupport import tiny_act

CONTROL_HZ = 30.0
POLICY_HZ = 30
DESCRIPTION = f"""
robot_config {{
  name: "bench"
  mode: MODE_INFERENCE
  node {{ name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "{tiny_act.CAMERA_TOPIC}" width: {tiny_act.WIDTH} height: {tiny_act.HEIGHT}
         qos_reliability: RELIABLE }}
  node {{ name: "follower" type: MOCK_ENCODER_PUBLISHER topic_name: "{tiny_act.STATE_TOPIC}" }}
  node {{
    name: "policy"
    type: INFERENCE
    topic_name: "/arm/commands"
    input_topics: ["{tiny_act.CAMERA_TOPIC}", "{tiny_act.STATE_TOPIC}"]
    rate_hz: {POLICY_HZ}
  }}
}}
"""
JOINT_STATE, JOINT_TRAJECTORY = "sensor_msgs/msg/JointState", "trajectory_msgs/msg/JointTrajectory"
FIRST_COMMAND_TIMEOUT_S = 300.0
STOP_TIMEOUT_S = 10.0
WARM_UP_S, QUICK_SECONDS = 2.0, 4.0


class Result:
    def __init__(self, label: str, commands: int, seconds: float, latencies_s: list[float], note: str = ""):
        self.label, self.rate, self.latencies_s, self.note = label, commands / seconds, latencies_s, note

    def row(self) -> str:
        if not self.latencies_s:
            return f"{self.label:<34} {self.rate:8.2f}  {'-':>9}  {'-':>9}  {self.note}"
        p50, p99 = (1000 * np.percentile(self.latencies_s, q) for q in (50, 99))
        return f"{self.label:<34} {self.rate:8.2f}  {p50:9.1f}  {p99:9.1f}  {len(self.latencies_s)} calls {self.note}"


class Peer:
    """This process on ROS: publishes the camera and arm state, and is the actuator (commands and latency)."""

    def __init__(self, settings: dict):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from sensor_msgs.msg import Image, JointState

        from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("bench_remote_inference", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        camera, state = settings["camera"]["topic"], settings["follower"]["topic"]
        images = self.node.create_publisher(Image, camera["name"], topic_qos(camera))
        states = self.node.create_publisher(JointState, state["name"], topic_qos(state))
        started = time.monotonic()

        def publish() -> None:
            t, stamp = time.monotonic() - started, self.node.get_clock().now().to_msg()
            images.publish(rgb_to_image(tiny_act.frame_image(t), stamp))
            states.publish(joint_state(tiny_act.JOINTS, tiny_act.pose(t), stamp))

        self.node.create_timer(1.0 / POLICY_HZ, publish)
        self.commands: list[float] = []
        self.latencies_s: list[float] = []
        self._stop = threading.Event()
        self._spinner = threading.Thread(target=self._spin, daemon=True)
        self._spinner.start()

    def _spin(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def now_s(self) -> float:
        return self.node.get_clock().now().nanoseconds / 1e9

    def follow_states(self, topic: dict) -> None:
        """(a): every JointState is a command; its latency is its age (stamped with the observation's time)."""
        from sensor_msgs.msg import JointState

        from joshua_runtime.ai.ros_arrays import stamp_seconds

        def receive(message) -> None:
            now = self.now_s()
            self.commands.append(now)
            self.latencies_s.append(now - stamp_seconds(message))

        self.node.create_subscription(JointState, topic["name"], receive, topic_qos(topic))

    def follow_chunks(self, topic: dict) -> None:
        """(b), (c): the actuators' chunk rule at CONTROL_HZ; a chunk's latency is its first executed command."""
        from trajectory_msgs.msg import JointTrajectory

        from joshua_runtime.nodes.trajectory_follower import TrajectoryFollower, chunk_from_trajectory

        rule = TrajectoryFollower(len(tiny_act.JOINTS))
        waiting: list[float] = []  # stamps of chunks accepted, not yet executed

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

    def close(self) -> None:
        self._stop.set()
        self._spinner.join()
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        self.context.try_shutdown()


def measure_node(label: str, settings: dict, message_type: str, seconds: float, env: dict) -> Result:
    """Run the policy node with this action topic type; measure `seconds` after the first command and WARM_UP_S."""
    policy = dict(settings["policy"], topic=dict(settings["policy"]["topic"], message_type=message_type))
    peer = Peer(settings)
    (peer.follow_chunks if message_type == JOINT_TRAJECTORY else peer.follow_states)(policy["topic"])
    process = subprocess.Popen(
        node_command(policy), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    output: list[str] = []
    reader = threading.Thread(target=lambda: output.extend(process.stdout), daemon=True)
    reader.start()
    try:
        deadline = time.monotonic() + FIRST_COMMAND_TIMEOUT_S
        while not peer.commands:
            if process.poll() is not None or time.monotonic() > deadline:
                raise SystemExit(f"{label}: no command reached the actuator:\n{''.join(output)}")
            time.sleep(0.05)
        time.sleep(WARM_UP_S)
        start, first_latency = peer.now_s(), len(peer.latencies_s)
        time.sleep(seconds)
        end = peer.now_s()
        commands = sum(1 for t in list(peer.commands) if start <= t < end)
        return Result(label, commands, end - start, peer.latencies_s[first_latency:])
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        peer.close()


def remote_chunked(settings: dict, seconds: float, env: dict) -> Result:
    """(c): (b) with the INFERENCE node in a network namespace of its own, reached over a veth pair.

    Not measured yet: it needs the multi-host build (a host per computer, DDS discovery across them,
    CompressedImage between hosts). When that exists, this function creates the namespace, starts the
    node in it with that host's settings, measures as measure_node does, and deletes the namespace.
    """
    return Result("(c) remote chunked (netns)", 0, 1.0, [], note="not measured: needs the multi-host set-up")


def lerobot_async(policy_dir: Path, seconds: float, env: dict) -> Result:
    from support import lerobot_async as async_inference

    executed, reactions = async_inference.measure(policy_dir, POLICY_HZ, seconds, WARM_UP_S, env)
    return Result("(d) LeRobot async (127.0.0.1)", len(executed), seconds, reactions)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="measurement per setup")
    parser.add_argument("--quick", action="store_true", help="a few seconds per setup (for the tests)")
    args = parser.parse_args()
    seconds = QUICK_SECONDS if args.quick else args.seconds
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    with tempfile.TemporaryDirectory(prefix="joshua-bench-remote-") as tmp:
        os.chdir(tmp)  # LeRobot's async inference writes logs/ into the working directory
        os.environ.setdefault("HF_LEROBOT_HOME", str(Path(tmp) / "lerobot-home"))
        env = bench_environment("remote_inference")
        os.environ.update(env)
        print(f"training the tiny ACT ({tiny_act.WIDTH}x{tiny_act.HEIGHT} camera, chunks of {tiny_act.CHUNK_SIZE})")
        policy_dir = train_quietly(Path(tmp))
        settings = compiled_settings(DESCRIPTION, [f"policy.model_path={policy_dir}"], "bench_remote_inference.pbtxt")
        print(
            f"ACT on CPU, camera and arm state at {POLICY_HZ} Hz, actuator at {CONTROL_HZ:g} Hz, "
            f"{seconds:g} s per setup after {WARM_UP_S:g} s of warm-up"
        )
        results = [
            measure_node("(a) sync, JointState", settings, JOINT_STATE, seconds, env),
            measure_node("(b) chunked, local", settings, JOINT_TRAJECTORY, seconds, env),
            remote_chunked(settings, seconds, env),
            lerobot_async(policy_dir, seconds, env),
        ]
    print(f"{'setup':<34} {'cmds/s':>8}  {'p50 ms':>9}  {'p99 ms':>9}")
    for result in results:
        print(result.row())
    floor = results[-1]
    for result in results[:2]:
        print(
            f"{result.label}: {result.rate / floor.rate:5.2f}x LeRobot async's commands/s, {result.rate / CONTROL_HZ:5.2f}x {CONTROL_HZ:g} Hz"
        )
    return 0


def train_quietly(workdir: Path) -> Path:
    """The tiny ACT, LeRobot's training log kept out of the figures."""
    code = f"from testsupport.tiny_act import train_tiny_act; print(train_tiny_act({str(workdir)!r}))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=dict(os.environ))
    if result.returncode != 0:
        raise SystemExit(f"training the tiny ACT failed:\n{result.stdout}{result.stderr}")
    return Path(result.stdout.strip().splitlines()[-1])


if __name__ == "__main__":
    sys.exit(main())
