"""The LEGO car end to end: `joshuac run` in simulation, and the real base node against the emulated hub."""

import os
import signal
import socket
import subprocess
import sys
import time

import pytest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from testsupport.compiled_settings import compiled_settings
from testsupport.joshuac_cli import ROOT

CONFIG = ROOT / "config" / "robots" / "lego_bot.pbtxt"
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
STARTUP_TIMEOUT_S = 40.0
SHUTDOWN_TIMEOUT_S = 10.0
SPEED_M_S = 0.1
DRIVE_S = 3.0
COMMAND_PERIOD_S = 0.1


def stop(process: subprocess.Popen) -> tuple[int, str]:
    process.send_signal(signal.SIGINT)
    try:
        output, _ = process.communicate(timeout=SHUTDOWN_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        output, _ = process.communicate()
        pytest.fail(f"did not stop within {SHUTDOWN_TIMEOUT_S} s:\n{output}")
    return process.returncode, output


def drive_and_coast(ros_client) -> tuple[float, float, float]:
    """Publish 0.1 m/s for 3 s, then nothing for 1.5 s: (x when the commands stop, x 1.5 s later, speed then)."""
    ros_client.listen("/odom", Odometry, RELIABLE)
    ros_client.listen("/wheel_states", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/odom") is not None, STARTUP_TIMEOUT_S), "no odometry"
    cmd_vel = ros_client.publisher("/cmd_vel", Twist, RELIABLE)
    ros_client.spin_until(lambda: cmd_vel.get_subscription_count() > 0, 10.0)
    start_x = ros_client.last("/odom").pose.pose.position.x
    command = Twist()
    command.linear.x = SPEED_M_S
    end = time.monotonic() + DRIVE_S
    while time.monotonic() < end:
        cmd_vel.publish(command)
        ros_client.spin_until(lambda: False, COMMAND_PERIOD_S)
    moved = ros_client.last("/odom").pose.pose.position.x - start_x
    ros_client.spin_until(lambda: False, 1.5)
    last = ros_client.last("/odom")
    return moved, last.pose.pose.position.x - start_x, last.twist.twist.linear.x


def test_the_simulated_car_drives_at_the_commanded_speed_and_stops_after_the_timeout(ros_env, ros_client):
    runner = subprocess.Popen(
        [sys.executable, "-m", "joshua_codegen", "run", str(CONFIG), "--set", "mode=MODE_SIMULATION"],
        env=ros_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        moved, coasted, speed_after = drive_and_coast(ros_client)
        wheels = ros_client.last("/wheel_states")
    finally:
        code, output = stop(runner)
    assert 0.25 <= moved <= 0.35, output
    assert abs(speed_after) < 0.005, "the car still moves after the command timeout"
    assert coasted - moved < 0.08, "the car went on after the command timeout"
    assert list(wheels.name) == ["left_wheel", "right_wheel"]
    assert code == 0, output


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_the_real_base_node_drives_the_emulated_hub_over_bluetooth(ros_env, ros_client, start_node):
    port = free_port()
    emulator = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "pybricks", "--port", str(port)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    try:
        assert "reachable over hci" in emulator.stdout.readline()
        settings = compiled_settings(CONFIG.read_text(), [f"base.ble_transport=tcp-client:127.0.0.1:{port}"])["base"]
        node = start_node(settings)
        moved, coasted, speed_after = drive_and_coast(ros_client)
        code, _, output = node.stop()
    finally:
        emulator.terminate()
        emulator.wait(5)
    assert 0.25 <= moved <= 0.35, output
    assert abs(speed_after) < 0.005 and coasted - moved < 0.08, output
    assert code == 0, output
