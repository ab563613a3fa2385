"""BLE command round trip to an emulated Pybricks hub, and the odometry rate of the LEGO car's base node.

    .venv/bin/python bench/lego.py [--quick]

Round trip: the driver writes a speed command to the hub program's stdin (ATT write with response)
and waits for the program's acknowledgement on stdout (GATT notification), through Bumble's full
HCI/L2CAP/ATT/GATT stack: once with hub and driver on one in-process link, once with the hub in a
`joshua-emulate pybricks` process reached over HCI on TCP. Odometry rate: the DIFF_DRIVE_BASE node
of config/robots/lego_bot.pbtxt (rate_hz 50) drives that emulated hub while Twist arrives at 10 Hz;
the bench counts /odom messages.
"""

import argparse
import os
import signal
import socket
import statistics
import subprocess
import sys
import time
from pathlib import Path

from support.described_nodes import compiled_settings, node_command

from joshua_runtime.drivers.pybricks import PybricksHub
from joshua_runtime.drivers.pybricks_bumble import BumbleTransport
from joshua_runtime.drivers.pybricks_program import program_blob
from joshua_runtime.emulators.pybricks_link import in_process

CONFIG = Path(__file__).resolve().parents[1] / "config" / "robots" / "lego_bot.pbtxt"
HUB = "Pybricks Hub"
STARTUP_TIMEOUT_S = 30.0


def round_trips(driver: PybricksHub, samples: int) -> list[float]:
    times = []
    for k in range(samples):
        elapsed = driver.set_speeds(k % 360, -(k % 360)).result(2.0)
        if elapsed is not None:
            times.append(elapsed * 1000)
    return times


def describe(label: str, times: list[float], samples: int) -> None:
    ordered = sorted(times)
    p99 = ordered[min(len(ordered) - 1, int(0.99 * len(ordered)))]
    print(f"{label}: p50 {statistics.median(ordered):.2f} ms, p99 {p99:.2f} ms ({len(times)}/{samples} acknowledged)")


def bench_in_process(samples: int, blob: bytes) -> None:
    driver = PybricksHub(HUB, None, blob)
    _, central = driver.run_on_loop(in_process(HUB), 5.0)
    driver.transport = BumbleTransport(device=central)
    started = time.perf_counter()
    driver.open()
    print(f"in-process link: connect, download and start {1000 * (time.perf_counter() - started):.0f} ms")
    try:
        describe("in-process link: command round trip", round_trips(driver, samples), samples)
    finally:
        driver.close()


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def bench_across_processes(samples: int, window_s: float, blob: bytes) -> None:
    port = free_port()
    emulator = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "pybricks", "--port", str(port)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    try:
        emulator.stdout.readline()
        driver = PybricksHub(HUB, BumbleTransport(hci=f"tcp-client:127.0.0.1:{port}"), blob)
        started = time.perf_counter()
        driver.open()
        print(f"HCI over TCP: connect, download and start {1000 * (time.perf_counter() - started):.0f} ms")
        try:
            describe("HCI over TCP: command round trip", round_trips(driver, samples), samples)
        finally:
            driver.close()
        odometry_rate(port, window_s)
    finally:
        emulator.send_signal(signal.SIGINT)
        emulator.wait(5)


def odometry_rate(port: int, window_s: float) -> None:
    import rclpy
    from geometry_msgs.msg import Twist
    from nav_msgs.msg import Odometry
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    settings = compiled_settings(CONFIG.read_text(), [f"base.ble_transport=tcp-client:127.0.0.1:{port}"])["base"]
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("ROS_DOMAIN_ID", str(os.getpid() % 100 + 100))
    base = subprocess.Popen(node_command(settings), env=os.environ)
    rclpy.init()
    node = rclpy.create_node("bench_lego")
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    stamps = []
    node.create_subscription(Odometry, "/odom", lambda _msg: stamps.append(time.monotonic()), qos)
    cmd_vel = node.create_publisher(Twist, "/cmd_vel", qos)
    try:
        deadline = time.monotonic() + STARTUP_TIMEOUT_S
        while not stamps and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.05)
        if not stamps:
            raise SystemExit("the base node published no odometry")
        command = Twist()
        command.linear.x = 0.1
        stamps.clear()
        end, next_command = time.monotonic() + window_s, 0.0
        while time.monotonic() < end:
            if time.monotonic() >= next_command:
                cmd_vel.publish(command)
                next_command = time.monotonic() + 0.1
            rclpy.spin_once(node, timeout_sec=0.01)
        gaps = [1000 * (b - a) for a, b in zip(stamps, stamps[1:])]
        print(
            f"odometry of the base node over BLE: {len(stamps) / window_s:.1f} Hz (rate_hz {settings['rate_hz']:g}), "
            f"largest gap {max(gaps):.0f} ms"
        )
    finally:
        node.destroy_node()
        rclpy.shutdown()
        base.send_signal(signal.SIGINT)
        base.wait(10)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer samples, shorter window")
    args = parser.parse_args()
    samples, window_s = (100, 3.0) if args.quick else (1000, 10.0)
    blob = program_blob()
    bench_in_process(samples, blob)
    bench_across_processes(samples, window_s, blob)


if __name__ == "__main__":
    main()
