"""Policies that keep the control rate: commands/s reaching the actuator and observation -> command latency.

    .venv/bin/python bench/remote_inference.py [--seconds 30] [--rounds 3] [--quick]

One real ACT (testsupport/tiny_act.py: LeRobot's ResNet-18 backbone on a 320x240 camera, chunks of 100
actions at 30 Hz, trained offline for a few steps) and the same data (that module's moving picture and
arm pose, published at 30 Hz), served four ways:

  (a) sync         the INFERENCE node with a JointState topic: one model call per published action
  (b) chunked      the INFERENCE node with a JointTrajectory topic: a background thread runs the model
                   while the actuator executes the last chunk
  (c) remote       (b) with the node on another host ("gpu") than the camera, arm and actuator ("robot"),
                   images as JPEG CompressedImage over the link between them (testsupport/hosts.py:
                   network namespaces joined by a bridge, each with its own /dev/shm)
  (d) lerobot      LeRobot's own async inference over the same link: policy_server on "gpu", RobotClient
                   with the bench's robot on "robot"

The robot side is a process of its own (support/chunk_peer.py; for (d) support/lerobot_async.py): it
publishes the data and is the actuator at CONTROL_HZ, following chunks with the actuators' own rule
(nodes/trajectory_follower.py). "commands/s": commands executed per second of measurement (a JointState
received; a control tick with a chunk in force; an action LeRobot's client sent to its robot).
"latency": from an observation's time (its header stamp; LeRobot's TimedObservation timestamp) to the
first command the actuator executes from the model call on it, p50 and p99 over the calls measured.
The setups take turns, round after round, so the machine's load falls on all of them alike; the
figures sum the rounds. (c) and (d) need root (network namespaces); without it (c) is not measured
and (d) runs on 127.0.0.1. --quick: one round without warm-up, each setup measured for a second or until
the latency of its first model call is in, whichever is later (for the tests).
"""

import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
from contextlib import ExitStack
from pathlib import Path

import numpy as np
from support.described_nodes import PYTHON, compiled_settings, node_command

from testsupport import tiny_act

CONTROL_HZ = 30.0  # the actuator's rate in support/chunk_peer.py
POLICY_HZ = 30
CAMERA_NODE = f"""name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "{tiny_act.CAMERA_TOPIC}"
         width: {tiny_act.WIDTH} height: {tiny_act.HEIGHT} qos_reliability: RELIABLE"""
DESCRIPTION = f"""
robot_config {{
  name: "bench"
  mode: MODE_INFERENCE
  node {{ {CAMERA_NODE} {{message_type}} }}
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
COMPRESSED = 'message_type: "sensor_msgs/msg/CompressedImage"'  # what (c) sends between hosts
JOINT_STATE, JOINT_TRAJECTORY = "sensor_msgs/msg/JointState", "trajectory_msgs/msg/JointTrajectory"
FIRST_COMMAND_TIMEOUT_S = 300.0
STOP_TIMEOUT_S = 10.0
MARGIN_S = 60.0  # beyond first command, warm-up and measurement, before a robot side is taken for hung
WARM_UP_S, QUICK_SECONDS = 2.0, 1.0
QUICK_CALLS = 1  # model calls a quick measurement waits for, so each setup's latency is measured
LEROBOT_PORT = 8080  # inside the "gpu" host's own namespace; on 127.0.0.1 a free port
BENCH = Path(__file__).resolve().parent
LABELS = {
    "a": "(a) sync, JointState",
    "b": "(b) chunked, local",
    "c": "(c) chunked, remote (netns)",
    "d": "(d) LeRobot async (netns)",
}


class Result:
    """One setup's figures, summed over its rounds."""

    def __init__(self, label: str, note: str = ""):
        self.label, self.note = label, note
        self.commands, self.seconds, self.latencies_s = 0, 0.0, []

    def add(self, measured: dict) -> None:
        self.commands += measured["commands"]
        self.seconds += measured["seconds"]
        self.latencies_s += measured["latencies_s"]

    @property
    def rate(self) -> float:
        return self.commands / self.seconds if self.seconds else 0.0

    def percentile_ms(self, q: float) -> float:
        return 1000 * float(np.percentile(self.latencies_s, q)) if self.latencies_s else float("nan")

    def row(self) -> str:
        if not self.seconds:
            return f"{self.label:<34} {'-':>8}  {'-':>9}  {'-':>9}  {self.note}"
        if not self.latencies_s:
            return f"{self.label:<34} {self.rate:8.2f}  {'-':>9}  {'-':>9}  {self.note}"
        p50, p99 = self.percentile_ms(50), self.percentile_ms(99)
        return f"{self.label:<34} {self.rate:8.2f}  {p50:9.1f}  {p99:9.1f}  {len(self.latencies_s)} calls {self.note}"


class Here:
    """Processes on this machine as it is (no namespace)."""

    address = "127.0.0.1"

    @staticmethod
    def free_port() -> int:
        with socket.socket() as probe:
            probe.bind((Here.address, 0))
            return probe.getsockname()[1]

    @staticmethod
    def popen(args, **popen_args) -> subprocess.Popen:
        return subprocess.Popen(args, **popen_args)


def stop(process: subprocess.Popen) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        process.wait(STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def collect(process: subprocess.Popen) -> list[str]:
    """The output lines of a process, gathered by a thread as they come."""
    lines: list[str] = []
    threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True).start()
    return lines


def robot_side(place, module: str, spec: dict, env: dict, timeout_s: float) -> dict:
    """Run a robot-side program (support.chunk_peer, support.lerobot_async) to its JSON result line."""
    # In the bench's working directory (LeRobot writes logs/ there), with bench/ on the path for `support`.
    env = dict(env, PYTHONPATH=os.pathsep.join(filter(None, [str(BENCH), env.get("PYTHONPATH", "")])))
    process = place.popen(
        [PYTHON, "-m", module, json.dumps(spec)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        stdout, stderr = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        process.kill()
        stdout, stderr = process.communicate()
    if not stdout.strip():
        return {"error": f"no result:\n{stderr[-3000:]}"}
    return json.loads(stdout.strip().splitlines()[-1])


def robot_side_timeout_s(window: dict) -> float:
    """How long a robot side may take: the first command, the first model calls a quick run waits for, its
    measurement and a margin."""
    return 2 * FIRST_COMMAND_TIMEOUT_S + window["seconds"] + MARGIN_S


def measure_node(settings: dict, message_type: str, window: dict, env: dict, node_place, robot_place) -> dict:
    """The policy node with this action type on `node_place`, the robot side on `robot_place`."""
    policy = dict(settings["policy"], topic=dict(settings["policy"]["topic"], message_type=message_type))
    node = node_place.popen(node_command(policy), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = collect(node)
    spec = {
        "camera": settings["camera"]["topic"],
        "state": settings["follower"]["topic"],
        "action": policy["topic"],
        **window,
        "first_command_timeout_s": FIRST_COMMAND_TIMEOUT_S,
    }
    timeout_s = robot_side_timeout_s(window)
    try:
        result = robot_side(robot_place, "support.chunk_peer", spec, env, timeout_s)
    finally:
        stop(node)
    if "error" in result:
        raise SystemExit(f"{result['error']}; the policy node said:\n{''.join(output[-40:])}")
    return result


def measure_lerobot(policy_dir: Path, window: dict, env: dict, server_place, client_place) -> dict:
    """LeRobot's policy server on `server_place`, its RobotClient with the bench's robot on `client_place`."""
    from support.lerobot_async import policy_server_command

    port = Here.free_port() if server_place is Here else LEROBOT_PORT
    scratch = tempfile.TemporaryDirectory(prefix="joshua-bench-lerobot-")  # LeRobot leaves a config copy there
    server = server_place.popen(
        policy_server_command(PYTHON, server_place.address, port, POLICY_HZ),
        env=dict(env, TMPDIR=scratch.name), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    spec = {
        "address": server_place.address,
        "port": port,
        "policy_dir": str(policy_dir),
        "fps": POLICY_HZ,
        **window,
        "first_command_timeout_s": FIRST_COMMAND_TIMEOUT_S,
    }
    timeout_s = robot_side_timeout_s(window)
    try:
        result = robot_side(client_place, "support.lerobot_async", spec, env, timeout_s)
    finally:
        stop(server)
        scratch.cleanup()
    if "error" in result:
        raise SystemExit(f"(d): {result['error']}")
    return result


def can_make_hosts() -> bool:
    return os.geteuid() == 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="measurement per setup, over all rounds")
    parser.add_argument("--rounds", type=int, default=3, help="turns each setup takes")
    parser.add_argument("--quick", action="store_true", help="one short round without warm-up (for the tests)")
    args = parser.parse_args()
    rounds = 1 if args.quick else max(1, args.rounds)
    seconds = QUICK_SECONDS if args.quick else args.seconds / rounds
    warm_up_s = 0.0 if args.quick else WARM_UP_S
    window = {"seconds": seconds, "warm_up_s": warm_up_s, "min_calls": QUICK_CALLS if args.quick else 0}
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    with tempfile.TemporaryDirectory(prefix="joshua-bench-remote-") as tmp, ExitStack() as stack:
        os.chdir(tmp)  # LeRobot's async inference writes logs/ into the working directory
        os.environ.setdefault("HF_LEROBOT_HOME", str(Path(tmp) / "lerobot-home"))
        from support.ros_env import bench_environment

        env = bench_environment("remote_inference")
        os.environ.update(env)
        print(f"training the tiny ACT ({tiny_act.WIDTH}x{tiny_act.HEIGHT} camera, chunks of {tiny_act.CHUNK_SIZE})")
        policy_dir = train_quietly(Path(tmp))
        model = [f"policy.model_path={policy_dir}"]
        raw = compiled_settings(DESCRIPTION.replace("{message_type}", ""), model, "bench_remote_inference.pbtxt")
        compressed = compiled_settings(DESCRIPTION.replace("{message_type}", COMPRESSED), model, "bench_remote.pbtxt")
        results = {key: Result(label) for key, label in LABELS.items()}
        setups = {
            "a": lambda: measure_node(raw, JOINT_STATE, window, env, Here, Here),
            "b": lambda: measure_node(raw, JOINT_TRAJECTORY, window, env, Here, Here),
        }
        if can_make_hosts():
            from testsupport.hosts import virtual_hosts

            hosts = stack.enter_context(virtual_hosts("robot", "gpu"))
            across = dict(env, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET")  # the subnet is the hosts' own switch
            robot, gpu = hosts["robot"], hosts["gpu"]
            setups["c"] = lambda: measure_node(compressed, JOINT_TRAJECTORY, window, across, gpu, robot)
            setups["d"] = lambda: measure_lerobot(policy_dir, window, across, gpu, robot)
        else:
            results["c"].note = "not measured: network namespaces need root"
            results["d"] = Result("(d) LeRobot async (127.0.0.1)", "no namespaces without root")
            setups["d"] = lambda: measure_lerobot(policy_dir, window, env, Here, Here)
        print(
            f"ACT on CPU, camera and arm state at {POLICY_HZ} Hz, actuator at {CONTROL_HZ:g} Hz, {rounds} round(s) of "
            f"{seconds:g} s per setup after {warm_up_s:g} s of warm-up, setups in turn"
        )
        for _ in range(rounds):
            for key, setup in setups.items():
                results[key].add(setup())
    print(f"{'setup':<34} {'cmds/s':>8}  {'p50 ms':>9}  {'p99 ms':>9}")
    for result in results.values():
        print(result.row())
    print_ratios(results)
    return 0


def print_ratios(results: dict[str, Result]) -> None:
    floor = results["d"]
    for key in ("a", "b", "c"):
        result = results[key]
        if not result.seconds:
            continue
        print(
            f"{result.label}: {result.rate / CONTROL_HZ:5.2f}x {CONTROL_HZ:g} Hz, {result.rate / floor.rate:5.2f}x "
            f"LeRobot's commands/s, p50 {result.percentile_ms(50) / floor.percentile_ms(50):5.2f}x and p99 "
            f"{result.percentile_ms(99) / floor.percentile_ms(99):5.2f}x LeRobot's latency"
        )


def train_quietly(workdir: Path) -> Path:
    """The tiny ACT, LeRobot's training log kept out of the figures."""
    code = f"from testsupport.tiny_act import train_tiny_act; print(train_tiny_act({str(workdir)!r}))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=dict(os.environ))
    if result.returncode != 0:
        raise SystemExit(f"training the tiny ACT failed:\n{result.stdout}{result.stderr}")
    return Path(result.stdout.strip().splitlines()[-1])


if __name__ == "__main__":
    sys.exit(main())
