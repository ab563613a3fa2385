"""The actuator's command watchdog and goal clamping, without ROS."""

import math

import pytest

from joshua_runtime.drivers.calibration import MotorCalibration
from joshua_runtime.nodes.command_guard import CommandWatchdog, clamp_goals


def test_watchdog_fires_once_per_silence_and_never_before_a_goal():
    watchdog = CommandWatchdog(0.5)
    assert not watchdog.expired(100.0)
    watchdog.feed(1.0)
    assert not watchdog.expired(1.4)
    assert watchdog.expired(1.5)
    assert not watchdog.expired(2.0)
    watchdog.feed(2.1)
    assert not watchdog.expired(2.5) and watchdog.expired(2.7)
    with pytest.raises(ValueError, match="must be positive"):
        CommandWatchdog(0)


def test_goals_outside_the_calibrated_range_are_clamped_and_named():
    motors = [
        MotorCalibration(1, 0, 0, 1000, 3000),
        MotorCalibration(2, 1, 0, 1000, 3000),
        MotorCalibration(3, 0, 0, 1000, 3000),
    ]
    ticks, clamped = clamp_goals(motors, ["pan", "lift", "elbow"], [0.5, 9.0, math.nan])
    assert ticks == {1: motors[0].to_ticks(0.5), 2: 1000}
    assert [c.joint for c in clamped] == ["lift"]
    assert clamped[0].describe() == f"lift goal 9.000 rad clamped to {motors[1].to_radians(1000):.3f} rad"
    _, at_the_edge = clamp_goals(motors[:1], ["pan"], [motors[0].to_radians(3000)])
    assert at_the_edge == []
