"""Differential-drive kinematics and odometry: straight lines, turns on the spot, arcs, limits."""

import math

import pytest

from joshua_runtime.odometry import Geometry, Odometry, limit_speeds, yaw_quaternion

LEGO = Geometry(wheel_radius_m=0.028, track_width_m=0.12)


def drive(geometry, left_rad_s, right_rad_s, seconds, steps=50):
    odometry = Odometry(geometry)
    for k in range(steps + 1):
        t = seconds * k / steps
        odometry.update(left_rad_s * t, right_rad_s * t, t)
    return odometry.pose


def test_wheel_speeds_and_body_velocity_are_inverse():
    left, right = LEGO.wheel_speeds(0.1, 0.5)
    assert LEGO.body_velocity(left, right) == pytest.approx((0.1, 0.5))
    assert LEGO.wheel_speeds(0.1, 0.0) == pytest.approx((0.1 / 0.028, 0.1 / 0.028))


def test_straight_line_covers_speed_times_time():
    pose = drive(LEGO, *LEGO.wheel_speeds(0.1, 0.0), seconds=3)
    assert (pose.x, pose.y, pose.yaw) == pytest.approx((0.3, 0.0, 0.0), abs=1e-9)
    assert pose.linear == pytest.approx(0.1)


def test_turn_on_the_spot_changes_only_yaw():
    pose = drive(LEGO, *LEGO.wheel_speeds(0.0, math.pi / 2), seconds=1)
    assert (pose.x, pose.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert pose.yaw == pytest.approx(math.pi / 2)
    assert pose.angular == pytest.approx(math.pi / 2)


@pytest.mark.parametrize("steps", [2, 7, 100])
def test_an_arc_is_exact_whatever_the_reading_rate(steps):
    # a quarter circle of radius 0.5 m
    pose = drive(LEGO, *LEGO.wheel_speeds(0.5 * math.pi / 2, math.pi / 2), seconds=1, steps=steps)
    assert (pose.x, pose.y, pose.yaw) == pytest.approx((0.5, 0.5, math.pi / 2), abs=1e-9)


def test_yaw_wraps_to_plus_minus_pi():
    pose = drive(LEGO, *LEGO.wheel_speeds(0.0, 3 * math.pi / 2), seconds=1)
    assert pose.yaw == pytest.approx(-math.pi / 2)


def test_limit_keeps_the_curvature():
    assert limit_speeds(10.0, 20.0, 10.0) == pytest.approx((5.0, 10.0))
    assert limit_speeds(-3.0, 2.0, 10.0) == (-3.0, 2.0)


def test_yaw_quaternion_is_unit_and_about_z():
    x, y, z, w = yaw_quaternion(math.pi / 2)
    assert (x, y) == (0.0, 0.0) and z * z + w * w == pytest.approx(1.0) and z == pytest.approx(math.sqrt(0.5))
