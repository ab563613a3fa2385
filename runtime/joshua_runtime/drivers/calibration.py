"""LeRobot-compatible servo calibration files and the raw ticks <-> radians conversion they define.

A file maps each motor name to `{"id", "drive_mode", "homing_offset", "range_min", "range_max"}`,
exactly as LeRobot's `calibration/*.json`. Present_Position already has `homing_offset` subtracted by
the servo, so a joint's zero is the middle of its range: radians = sign * (ticks - middle) *
RADIANS_PER_TICK, with sign -1 for drive_mode 1. The scale is LeRobot's DEGREES scale (4095 ticks
per turn), so radians converted to degrees equal LeRobot's normalised values. Commands are clamped
to [range_min, range_max]; readings are not.
"""

import json
import math
import os
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

from joshua_runtime.drivers.sts3215_table import MAX_TICK
from joshua_runtime.errors import SettingsError

RADIANS_PER_TICK = 2 * math.pi / MAX_TICK
FIELDS = ("id", "drive_mode", "homing_offset", "range_min", "range_max")
HALF_TURN_TICKS = MAX_TICK // 2  # LeRobot homes the middle pose at 2047


@dataclass(frozen=True)
class MotorCalibration:
    id: int
    drive_mode: int = 0
    homing_offset: int = 0
    range_min: int = 0
    range_max: int = MAX_TICK

    @property
    def middle(self) -> float:
        return (self.range_min + self.range_max) / 2

    @property
    def sign(self) -> int:
        return -1 if self.drive_mode else 1

    def to_radians(self, ticks: float) -> float:
        return self.sign * (ticks - self.middle) * RADIANS_PER_TICK

    def speed_to_radians(self, ticks_per_s: float) -> float:
        return self.sign * ticks_per_s * RADIANS_PER_TICK

    def unclamped_ticks(self, radians: float) -> int:
        """The raw position of a joint angle, in or out of the calibrated range."""
        return round(self.middle + self.sign * radians / RADIANS_PER_TICK)

    def to_ticks(self, radians: float) -> int:
        """The goal for a joint angle, clamped to the calibrated range."""
        return min(max(self.unclamped_ticks(radians), self.range_min), self.range_max)

    def speed_to_ticks(self, radians_per_s: float) -> int:
        return round(abs(radians_per_s) / RADIANS_PER_TICK)


def uncalibrated(servo_id: int) -> MotorCalibration:
    """The identity calibration: full turn, no offset."""
    return MotorCalibration(id=servo_id)


def load_calibration(path: str | os.PathLike) -> dict[str, MotorCalibration]:
    """Read a LeRobot calibration JSON; SettingsError names the file and the problem."""
    path = Path(path)
    try:
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise SettingsError(f"calibration file {path} not found") from None
    except (OSError, ValueError) as exc:
        raise SettingsError(f"calibration file {path} is unreadable: {exc}") from None
    if not isinstance(document, dict):
        raise SettingsError(f"calibration file {path}: expected an object of motor names")
    motors = {}
    for name, entry in document.items():
        if not isinstance(entry, dict) or any(not isinstance(entry.get(field), int) for field in FIELDS):
            raise SettingsError(f"calibration file {path}: motor {name!r} needs integer fields {', '.join(FIELDS)}")
        motor = MotorCalibration(**{field: entry[field] for field in FIELDS})
        if motor.range_min >= motor.range_max:
            raise SettingsError(f"calibration file {path}: motor {name!r} has range_min >= range_max")
        motors[name] = motor
    return motors


def calibration_for_bus(
    path: str | os.PathLike | None, joint_names: list[str], ids: list[int]
) -> list[MotorCalibration]:
    """One calibration per servo in bus order: from the file (matched by joint name) or the identity."""
    if not path:
        return [uncalibrated(servo_id) for servo_id in ids]
    motors = load_calibration(path)
    missing = [name for name in joint_names if name not in motors]
    if missing:
        raise SettingsError(f"calibration file {path} has no entry for {', '.join(missing)}")
    calibrations = [motors[name] for name in joint_names]
    for name, servo_id, motor in zip(joint_names, ids, calibrations):
        if motor.id != servo_id:
            raise SettingsError(f"calibration file {path}: {name} has id {motor.id}, the bus uses id {servo_id}")
    return calibrations


def save_calibration(path: str | os.PathLike, motors: dict[str, MotorCalibration]) -> None:
    """Write the file atomically (a crash leaves the previous calibration intact)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps({name: asdict(motor) for name, motor in motors.items()}, indent=4) + "\n"
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "w") as stream:
            stream.write(text)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
