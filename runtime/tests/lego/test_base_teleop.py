"""Teleoperation: keys and gamepad sticks to body velocities, and joshua-teleop publishing Twist from a pty."""

import os
import subprocess
import sys
import termios
import time

import pytest
from geometry_msgs.msg import Twist
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Joy

from joshua_runtime.teleop.cli import split_keys
from joshua_runtime.teleop.mapping import KeyboardTeleop, joy_velocity

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
TELEOP = [sys.executable, "-m", "joshua_runtime.teleop.cli"]


def test_keys_choose_a_motion_that_lasts_and_plus_minus_scale_it():
    teleop = KeyboardTeleop(max_linear=0.2, max_angular=2.0)
    assert teleop.velocity() == (0.0, 0.0)
    teleop.press("w")
    assert teleop.velocity() == (0.2, 0.0)
    teleop.press("+")
    assert teleop.velocity() == pytest.approx((0.22, 0.0))
    teleop.press("\x1b[D")
    assert teleop.velocity() == pytest.approx((0.0, 2.2))
    assert not teleop.press("k")
    teleop.press(" ")
    assert teleop.velocity() == (0.0, 0.0)


def test_arrow_keys_are_one_key_each():
    assert split_keys("w\x1b[Ad") == ["w", "\x1b[A", "d"]
    assert split_keys("\x1b") == ["\x1b"]


def test_sticks_drive_within_the_top_speeds_and_only_with_the_enable_button_held():
    assert joy_velocity([0.5, 1.0], [], 0.2, 2.0) == (0.2, 1.0)
    assert joy_velocity([0.01, -0.02], [], 0.2, 2.0) == (0.0, 0.0)
    assert joy_velocity([0.0, 1.0], [0, 0], 0.2, 2.0, enable_button=1) == (0.0, 0.0)
    assert joy_velocity([0.0, 1.0], [0, 1], 0.2, 2.0, enable_button=1) == (0.2, 0.0)


def test_keys_typed_in_a_terminal_become_twists_and_quitting_stops_the_base(ros_env, ros_client):
    ros_client.listen("/cmd_vel", Twist, RELIABLE)
    controller, terminal = os.openpty()
    teleop = subprocess.Popen(TELEOP, stdin=terminal, stdout=terminal, stderr=subprocess.STDOUT, env=ros_env)
    os.close(terminal)
    try:
        assert ros_client.spin_until(lambda: ros_client.last("/cmd_vel") is not None, 20.0), "no Twist"
        # Keys reach the program only once it has left canonical mode (the pty's settings are shared).
        deadline = time.monotonic() + 20.0
        while termios.tcgetattr(controller)[3] & termios.ICANON and time.monotonic() < deadline:
            time.sleep(0.05)
        os.write(controller, b"w")
        assert ros_client.spin_until(lambda: ros_client.last("/cmd_vel").linear.x == pytest.approx(0.2), 5.0)
        os.write(controller, b"a")
        assert ros_client.spin_until(lambda: ros_client.last("/cmd_vel").angular.z == pytest.approx(2.0), 5.0)
        os.write(controller, b"\x1b")
        assert teleop.wait(10) == 0
        assert ros_client.spin_until(lambda: ros_client.last("/cmd_vel").angular.z == 0.0, 5.0)
    finally:
        teleop.kill()
        os.close(controller)


def test_joy_messages_become_twists(ros_env, ros_client):
    ros_client.listen("/cmd_vel", Twist, RELIABLE)
    teleop = subprocess.Popen(TELEOP + ["--joy", "/joy"], stdin=subprocess.DEVNULL, env=ros_env)
    try:
        joy = ros_client.publisher("/joy", Joy, RELIABLE)
        stick = Joy(axes=[-1.0, 0.5], buttons=[0])
        assert ros_client.spin_until(
            lambda: (ros_client.last("/cmd_vel") or Twist()).linear.x == pytest.approx(0.1),
            20.0,
            every=lambda: joy.publish(stick),
        )
        assert ros_client.last("/cmd_vel").angular.z == pytest.approx(-2.0)
    finally:
        teleop.terminate()
        assert teleop.wait(10) == 0


@pytest.mark.process
def test_keys_need_a_terminal():
    result = subprocess.run(TELEOP, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert "keys are read from a terminal" in result.stderr
