"""Leader-to-follower latency (p50/p99) and sustained loop rate of SO-100 teleoperation on emulated buses.

    .venv/bin/python bench/teleop.py [--rate-hz 200] [--samples 600] [--quick]

Two STS3215 emulators (6 servos each, 1 Mbaud wire time emulated) run in this process; an
ENCODER_PUBLISHER process reads the leader bus and publishes /leader/joint_states (RELIABLE), an
ACTUATOR_SUBSCRIBER process SYNC_WRITEs the follower bus from it, both at --rate-hz. Each sample
turns the leader's servo 1 by hand and measures until the follower emulator receives that goal.
Samples are spaced by a random fraction of the period so they land at every phase of the leader's
read cycle. Each latency is split into the wait for the leader's next SYNC_READ (about half a
period on average, whatever the software) and the pipeline from that read to the follower's goal
(wire time, both processes, DDS). The loop rate is the rate of goal SYNC_WRITEs the follower receives. --quick: 20 samples, a 1 s window.
"""

import argparse
import bisect
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from support.described_nodes import compiled_settings, node_command
from support.ros_env import bench_environment

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import register
from joshua_runtime.emulators.sts3215 import Sts3215Emulator

# The follower mirrors the leader. Each run sets the serial ports (the emulators' links) and the
# rates (--rate-hz) with `--set`; servo ids 1-6, SO-100 joint names and 1 Mbaud are the bus defaults.
DESCRIPTION = """
robot_config {
  name: "bench_teleop"
  mode: MODE_TELEOPERATION
  node {
    name: "bench_leader"
    type: ENCODER_PUBLISHER
    topic_name: "/leader/joint_states"
  }
  node {
    name: "bench_follower"
    type: ACTUATOR_SUBSCRIBER
    topic_name: "/leader/joint_states"
  }
}
"""
STARTUP_TIMEOUT_S = 60.0
SAMPLE_TIMEOUT_S = 1.0
SETTLE_S = 0.02  # pause after a sample so the follower has finished writing it
RATE_WINDOW_S = 5.0
QUICK_RATE_WINDOW_S, QUICK_SAMPLES = 1.0, 20
STOP_TIMEOUT_S = 5.0
GOAL_ADDRESS = register("Goal_Position").address
LOW_TICKS, HIGH_TICKS = 1500, 2600


def node_settings(leader_port: Path, follower_port: Path, rate_hz: float) -> list[dict]:
    """Settings of the leader and follower nodes on the given buses."""
    settings = compiled_settings(
        DESCRIPTION,
        [
            f"bench_leader.serial_port={leader_port}",
            f"bench_follower.serial_port={follower_port}",
            f"bench_leader.rate_hz={rate_hz}",
            f"bench_follower.rate_hz={rate_hz}",
        ],
        "bench_teleop.pbtxt",
    )
    return [settings["bench_leader"], settings["bench_follower"]]


def start(settings: dict, env: dict) -> subprocess.Popen:
    return subprocess.Popen(node_command(settings), env=env, stderr=subprocess.PIPE, text=True)


def stop(process: subprocess.Popen) -> int:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        process.communicate(timeout=STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
    return process.returncode


class GoalWatch:
    """Timestamps, in the follower emulator's thread, each goal servo 1 receives."""

    def __init__(self):
        self.condition = threading.Condition()
        self.last_goal: tuple[int, float] | None = None
        self.writes = 0

    def __call__(self, servo_id: int, address: int, data: bytes, now: float) -> None:
        if servo_id != 1 or address != GOAL_ADDRESS:
            return
        with self.condition:
            self.writes += 1
            self.last_goal = (int.from_bytes(data[:2], "little"), now)
            self.condition.notify_all()

    def wait_for(self, goal: int, timeout_s: float) -> float | None:
        deadline = time.monotonic() + timeout_s
        with self.condition:
            while self.last_goal is None or self.last_goal[0] != goal:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return None
                self.condition.wait(remaining)
            return self.last_goal[1]


class ReadLog:
    """Monotonic times of the SYNC_READs the leader bus serves."""

    def __init__(self):
        self.times: list[float] = []

    def __call__(self, packet: proto.Packet, now: float) -> None:
        if packet.code == proto.INST_SYNC_READ:
            self.times.append(now)

    def first_after(self, moment: float) -> float | None:
        index = bisect.bisect_left(self.times, moment)
        return self.times[index] if index < len(self.times) else None


def percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rate-hz", type=float, default=200.0)
    parser.add_argument("--samples", type=int, default=600)
    parser.add_argument(
        "--quick", action="store_true", help=f"{QUICK_SAMPLES} samples, a 1 s rate window (for the tests)"
    )
    args = parser.parse_args()
    window_s = QUICK_RATE_WINDOW_S if args.quick else RATE_WINDOW_S
    args.samples = QUICK_SAMPLES if args.quick else args.samples
    env = bench_environment("teleop")
    period = 1.0 / args.rate_hz
    jitter = random.Random(0)
    with tempfile.TemporaryDirectory() as directory:
        leader_link, follower_link = Path(directory) / "ttyLEADER", Path(directory) / "ttyFOLLOWER"
        leader, follower = node_settings(leader_link, follower_link, args.rate_hz)
        leader_bus = Sts3215Emulator(leader_link, leader["device_ids"]).start()
        follower_bus = Sts3215Emulator(follower_link, follower["device_ids"]).start()
        watch = GoalWatch()
        follower_bus.write_listeners.append(watch)
        reads = ReadLog()
        leader_bus.packet_listeners.append(reads)
        nodes = [start(leader, env), start(follower, env)]
        try:
            if watch.wait_for(2048, STARTUP_TIMEOUT_S) is None:
                failed = [n.stderr.read() for n in nodes if n.poll() is not None]
                print("no goal reached the follower; node stderr:", failed)
                return 1
            reads_before, writes_before = leader_bus.stats["packets"], watch.writes
            window_start = time.monotonic()
            time.sleep(window_s)
            window = time.monotonic() - window_start
            read_rate = (leader_bus.stats["packets"] - reads_before) / window
            write_rate = (watch.writes - writes_before) / window

            latencies, waits, missed = [], [], 0
            for index in range(args.samples):
                goal = HIGH_TICKS if index % 2 == 0 else LOW_TICKS
                time.sleep(SETTLE_S + jitter.random() * period)
                moved_at = time.monotonic()
                leader_bus.move_by_hand(1, goal)
                arrived_at = watch.wait_for(goal, SAMPLE_TIMEOUT_S)
                if arrived_at is None:
                    missed += 1
                else:
                    latencies.append(arrived_at - moved_at)
                    waits.append(reads.first_after(moved_at) - moved_at)
        finally:
            codes = [stop(node) for node in nodes]
            leader_bus.stop()
            follower_bus.stop()
    ms = [1000 * value for value in latencies]
    wait_ms = [1000 * value for value in waits]
    pipeline_ms = [total - wait for total, wait in zip(ms, wait_ms)]
    print(f"teleop over emulated 1 Mbaud STS3215 buses, 6 servos, nodes at {args.rate_hz:g} Hz")
    print(
        f"  leader-to-follower latency over {len(ms)} samples ({missed} missed): "
        f"p50 {percentile(ms, 0.5):.2f} ms, p99 {percentile(ms, 0.99):.2f} ms, "
        f"mean {statistics.fmean(ms):.2f} ms, max {max(ms):.2f} ms"
    )
    print(
        f"    of which waiting for the leader's next read: p50 {percentile(wait_ms, 0.5):.2f} ms; read to "
        f"follower goal: p50 {percentile(pipeline_ms, 0.5):.2f} ms, p99 {percentile(pipeline_ms, 0.99):.2f} ms"
    )
    print(
        f"  sustained loop rate: {write_rate:.1f} goal writes/s on the follower, "
        f"{read_rate:.1f} bus transactions/s on the leader"
    )
    print(f"  node exit codes on SIGINT: {codes}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
