"""Guards for an actuator's goals, free of ROS: a command watchdog, and clamping that says what it clamped.

watchdog = CommandWatchdog(timeout_s=0.5)
watchdog.feed(now)                        # on every goal received
if watchdog.expired(now): stop_actuator() # once per silence; feed() re-arms it
ticks, clamped = clamp_goals(calibrations, names, radians)
"""

import math
from dataclasses import dataclass

from joshua_runtime.drivers.calibration import MotorCalibration


class CommandWatchdog:
    """Fires once when no goal arrived for `timeout_s`; the next goal re-arms it. Never fires before a first goal."""

    def __init__(self, timeout_s: float):
        if timeout_s <= 0:
            raise ValueError("the command timeout must be positive")
        self.timeout_s = timeout_s
        self._last_goal_s: float | None = None
        self._fired = False

    def feed(self, now_s: float) -> None:
        self._last_goal_s = now_s
        self._fired = False

    def expired(self, now_s: float) -> bool:
        """True once per silence longer than the timeout."""
        if self._last_goal_s is None or self._fired or now_s - self._last_goal_s < self.timeout_s:
            return False
        self._fired = True
        return True


@dataclass(frozen=True)
class ClampedGoal:
    joint: str
    requested: float  # rad
    applied: float  # rad, the nearest goal inside the calibrated range

    def describe(self) -> str:
        return f"{self.joint} goal {self.requested:.3f} rad clamped to {self.applied:.3f} rad"


def clamp_goals(
    calibrations: list[MotorCalibration], joints: list[str], goals: list[float]
) -> tuple[dict[int, int], list[ClampedGoal]]:
    """Raw goals by servo id (NaN goals skipped), and every goal that fell outside its calibrated range."""
    ticks, clamped = {}, []
    for motor, joint, goal in zip(calibrations, joints, goals):
        if math.isnan(goal):
            continue
        raw = ticks[motor.id] = motor.to_ticks(goal)
        if raw != motor.unclamped_ticks(goal):
            clamped.append(ClampedGoal(joint, goal, motor.to_radians(raw)))
    return ticks, clamped
