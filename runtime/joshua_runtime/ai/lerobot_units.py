"""Joint values as LeRobot's SO-100/SO-101 follower reads them, from the radians on the topics (units LEROBOT).

LeRobot (0.4.x, `lerobot.motors.motors_bus.MotorsBus._normalize`) turns a servo's raw position `t`
into a value with its calibration file (range_min, range_max, drive_mode per motor; mid = the middle
of the range, 4095 ticks per turn):

- DEGREES (every joint but the gripper, `use_degrees=True`, LeRobot's default): (t - mid) * 360 / 4095,
  drive_mode ignored, not clamped;
- RANGE_M100_100 (the same joints with `use_degrees=False`; units LEROBOT_RANGE here): t clamped to
  the range, (t - min) / (max - min) * 200 - 100, negated for drive_mode 1;
- RANGE_0_100 (the joint named `gripper`, always): t clamped, (t - min) / (max - min) * 100, and
  100 minus that for drive_mode 1.

The servo nodes publish radians = sign * (t - mid) * 2 pi / 4095 with the same file
(drivers/calibration.py), so `t` is recovered exactly (not rounded: a simulated arm's angles fall
between ticks). Joints are matched by name with the file's motors.
"""

import numpy as np

from joshua_runtime.drivers.calibration import RADIANS_PER_TICK, MotorCalibration, load_calibration
from joshua_runtime.drivers.sts3215_table import MAX_TICK
from joshua_runtime.errors import SettingsError

SI, LEROBOT, LEROBOT_RANGE = "SI", "LEROBOT", "LEROBOT_RANGE"
UNITS = (SI, LEROBOT, LEROBOT_RANGE)
GRIPPER = "gripper"  # LeRobot's SO follower reads its gripper in 0..100 whatever use_degrees says


def degrees(motor: MotorCalibration, ticks: np.ndarray) -> np.ndarray:
    return (ticks - motor.middle) * 360.0 / MAX_TICK  # LeRobot: its resolution table's 4096, minus one


def range_m100_100(motor: MotorCalibration, ticks: np.ndarray) -> np.ndarray:
    bounded = np.clip(ticks, motor.range_min, motor.range_max)
    value = (bounded - motor.range_min) / (motor.range_max - motor.range_min) * 200.0 - 100.0
    return -value if motor.drive_mode else value


def range_0_100(motor: MotorCalibration, ticks: np.ndarray) -> np.ndarray:
    bounded = np.clip(ticks, motor.range_min, motor.range_max)
    value = (bounded - motor.range_min) / (motor.range_max - motor.range_min) * 100.0
    return 100.0 - value if motor.drive_mode else value


class JointUnits:
    """Converts the positions of named joints from radians into the convention `units` names."""

    def __init__(self, units: str, calibration_file: str = ""):
        if units not in UNITS:
            raise SettingsError(f"units {units!r} is not one of {', '.join(UNITS)}")
        self.units = units
        self.calibration_file = calibration_file
        self.motors: dict[str, MotorCalibration] = {}
        if units != SI:
            if not calibration_file:
                raise SettingsError(f"units {units} needs the follower's calibration_file")
            self.motors = load_calibration(calibration_file)

    @property
    def converts(self) -> bool:
        return self.units != SI

    def check_joints(self, joints: list[str]) -> None:
        """Refuse joints the calibration file does not know (SettingsError naming them)."""
        missing = [joint for joint in joints if joint not in self.motors]
        if self.converts and missing:
            raise SettingsError(
                f"calibration file {self.calibration_file} has no motor named {', '.join(missing)} "
                f"(units {self.units} converts joints by name; it has {', '.join(self.motors)})"
            )

    def from_radians(self, joints: list[str], radians: np.ndarray) -> np.ndarray:
        """The values LeRobot would read for these joints at these angles (float32, in joint order)."""
        if not self.converts:
            return radians
        values = np.empty(len(joints), dtype=np.float64)
        for i, (joint, angle) in enumerate(zip(joints, radians)):
            motor = self.motors[joint]
            ticks = motor.middle + motor.sign * float(angle) / RADIANS_PER_TICK
            values[i] = self._normalize(joint, motor, np.float64(ticks))
        return values.astype(np.float32)

    def _normalize(self, joint: str, motor: MotorCalibration, ticks):
        if joint == GRIPPER:
            return range_0_100(motor, ticks)
        if self.units == LEROBOT:
            return degrees(motor, ticks)
        return range_m100_100(motor, ticks)
