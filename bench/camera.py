"""Cross-process latency (p50/p99) and drop rate of 640x480 bgr8 images at 30 fps, with and without the Fast DDS profile.

    .venv/bin/python bench/camera.py [--seconds 10] [--only with|without] [--quick]

A MOCK_CAMERA_PUBLISHER node process publishes; a subscriber process (this file with
--subscribe) measures receive time - header stamp and counts missing frames from the frame
number encoded in the scrolling pattern. Both use the camera's default QoS (keep-last 5, best
effort, volatile). "with": both processes get FASTRTPS_DEFAULT_PROFILES_FILE set to the profile
joshuac writes for the camera node; "without": Fast DDS defaults. --quick: 1 s of the "with" case.
"""

import argparse
import json
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from support.described_nodes import PYTHON, compiled_settings, node_command, topic_qos, write_fastdds_profiles
from support.ros_env import bench_environment

WIDTH, HEIGHT, RATE_HZ = 640, 480, 30.0
# The publisher; it and the subscriber use its topic and the camera's default QoS.
DESCRIPTION = f"""
robot_config {{
  name: "bench"
  mode: MODE_TELEOPERATION
  node {{
    name: "bench_camera"
    type: MOCK_CAMERA_PUBLISHER
    topic_name: "/bench/camera/image"
    width: {WIDTH}
    height: {HEIGHT}
    rate_hz: {RATE_HZ}
  }}
}}
"""
WARMUP_S = 2.0  # frames received during discovery and start-up are not counted
SUBSCRIBER_GRACE_S = 30.0
STOP_TIMEOUT_S = 5.0
SCROLL_PX = 8  # mock_camera_publisher.SCROLL_PX: frame n is scrolled by n x 8 px
PATTERN_PERIOD = WIDTH // SCROLL_PX


def publisher_settings() -> dict:
    return compiled_settings(DESCRIPTION, path="bench_camera.pbtxt")["bench_camera"]


def frame_number(data) -> int:
    """Frame number modulo PATTERN_PERIOD: where the blue gradient of row 0 restarts at 0."""
    row = memoryview(bytes(data[: WIDTH * 3]))
    for x in range(WIDTH):
        if row[3 * x] == 0:
            return (x // SCROLL_PX) % PATTERN_PERIOD
    return -1


def subscribe(seconds: float) -> None:
    """Subscriber process: print one JSON line of measurements after `seconds` of counted frames."""
    import rclpy
    from sensor_msgs.msg import Image

    rclpy.init()
    node = rclpy.create_node("bench_camera_subscriber")
    latencies_ms, numbers, first = [], [], {}

    def received(message: Image) -> None:
        now = time.time_ns()
        first.setdefault("t", time.monotonic())
        if time.monotonic() - first["t"] < WARMUP_S:
            return
        stamp = message.header.stamp.sec * 1_000_000_000 + message.header.stamp.nanosec
        latencies_ms.append((now - stamp) / 1e6)
        numbers.append(frame_number(message.data))

    topic = publisher_settings()["topic"]
    node.create_subscription(Image, topic["name"], received, topic_qos(topic))
    deadline = time.monotonic() + SUBSCRIBER_GRACE_S + seconds
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
        if "t" in first and time.monotonic() - first["t"] > WARMUP_S + seconds:
            break
    missing = sum((b - a) % PATTERN_PERIOD - 1 for a, b in zip(numbers, numbers[1:]) if a >= 0 and b >= 0)
    print(json.dumps({"received": len(numbers), "missing": missing, "latencies_ms": latencies_ms}), flush=True)
    node.destroy_node()
    rclpy.shutdown()


def percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))] if ordered else float("nan")


def run_case(publisher: dict, profile: Path | None, seconds: float) -> dict:
    env = bench_environment("camera")
    env.pop("FASTRTPS_DEFAULT_PROFILES_FILE", None)
    if profile is not None:
        env["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(profile)
    process = subprocess.Popen(node_command(publisher), env=env, stderr=subprocess.DEVNULL)
    try:
        result = subprocess.run(
            [PYTHON, __file__, "--subscribe", "--seconds", str(seconds)],
            env=env,
            capture_output=True,
            text=True,
            timeout=SUBSCRIBER_GRACE_S + seconds + WARMUP_S + 10,
        )
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(STOP_TIMEOUT_S)
    data = json.loads(result.stdout.strip().splitlines()[-1])
    expected = data["received"] + data["missing"]
    return {
        "received": data["received"],
        "missing": data["missing"],
        "drop_rate": data["missing"] / expected if expected else 1.0,
        "p50_ms": percentile(data["latencies_ms"], 0.50),
        "p99_ms": percentile(data["latencies_ms"], 0.99),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="measured time per case")
    parser.add_argument("--only", choices=("with", "without"), help="run one case")
    parser.add_argument("--quick", action="store_true", help="1 s of the 'with' case (for the tests)")
    parser.add_argument("--subscribe", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.subscribe:
        subscribe(args.seconds)
        return 0
    if args.quick:
        args.seconds, args.only = 1.0, "with"
    publisher = publisher_settings()
    with tempfile.TemporaryDirectory() as tmp:
        profile = write_fastdds_profiles(DESCRIPTION, Path(tmp), path="bench_camera.pbtxt")["bench_camera"]
        cases = [("with", profile), ("without", None)]
        print(
            f"640x480 bgr8 Image ({WIDTH * HEIGHT * 3} bytes) at {RATE_HZ:g} fps, best effort depth 5, "
            f"{args.seconds:g} s per case, ROS_DOMAIN_ID {bench_environment('camera')['ROS_DOMAIN_ID']}"
        )
        print(f"{'profile':<8} {'received':>8} {'missing':>8} {'drop %':>7} {'p50 ms':>8} {'p99 ms':>8}")
        for name, path in cases:
            if args.only and name != args.only:
                continue
            r = run_case(publisher, path, args.seconds)
            print(
                f"{name:<8} {r['received']:>8} {r['missing']:>8} {100 * r['drop_rate']:>7.1f} "
                f"{r['p50_ms']:>8.2f} {r['p99_ms']:>8.2f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
