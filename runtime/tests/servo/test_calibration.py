"""LeRobot calibration files: format, validation, and the ticks <-> radians conversion both ways."""

import json
import math

import pytest

from joshua_runtime.drivers.calibration import (
    RADIANS_PER_TICK,
    MotorCalibration,
    calibration_for_bus,
    load_calibration,
    save_calibration,
)
from joshua_runtime.errors import SettingsError

LEROBOT_FILE = {
    "shoulder_pan": {"id": 1, "drive_mode": 0, "homing_offset": -1470, "range_min": 758, "range_max": 3292},
    "gripper": {"id": 6, "drive_mode": 1, "homing_offset": 1407, "range_min": 2031, "range_max": 3476},
}


def test_round_trip_keeps_lerobot_layout(tmp_path):
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(LEROBOT_FILE))
    motors = load_calibration(path)
    assert motors["gripper"] == MotorCalibration(6, 1, 1407, 2031, 3476)
    save_calibration(tmp_path / "copy" / "arm.json", motors)
    saved = json.loads((tmp_path / "copy" / "arm.json").read_text())
    assert saved == LEROBOT_FILE
    assert list(saved["shoulder_pan"]) == ["id", "drive_mode", "homing_offset", "range_min", "range_max"]


def test_radians_are_lerobot_degrees_around_the_middle():
    pan = MotorCalibration(1, 0, 0, 758, 3292)
    middle = (758 + 3292) / 2
    assert pan.to_radians(middle) == 0.0
    lerobot_degrees = (3000 - middle) * 360 / 4095
    assert math.degrees(pan.to_radians(3000)) == pytest.approx(lerobot_degrees)
    assert pan.to_ticks(pan.to_radians(3000)) == 3000
    assert pan.to_ticks(10.0) == 3292 and pan.to_ticks(-10.0) == 758


def test_drive_mode_inverts_the_direction():
    inverted = MotorCalibration(6, 1, 0, 1000, 3000)
    assert inverted.to_radians(2100) == pytest.approx(-100 * RADIANS_PER_TICK)
    assert inverted.to_ticks(-100 * RADIANS_PER_TICK) == 2100
    assert inverted.speed_to_radians(50) == pytest.approx(-50 * RADIANS_PER_TICK)


def test_bus_order_and_identity_without_file(tmp_path):
    assert calibration_for_bus("", ["a", "b"], [4, 5]) == [MotorCalibration(4), MotorCalibration(5)]
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(LEROBOT_FILE))
    pair = calibration_for_bus(path, ["gripper", "shoulder_pan"], [6, 1])
    assert [m.id for m in pair] == [6, 1]


@pytest.mark.parametrize(
    ("document", "message"),
    [
        (None, r"calibration file .*arm.json not found$"),
        ("[1]", r"expected an object of motor names$"),
        ('{"a": {"id": 1}}', r"motor 'a' needs integer fields id, drive_mode, homing_offset, range_min, range_max$"),
        (
            '{"a": {"id": 1, "drive_mode": 0, "homing_offset": 0, "range_min": 9, "range_max": 9}}',
            r"range_min >= range_max$",
        ),
        ("{not json", r"is unreadable"),
    ],
)
def test_bad_files_are_settings_errors(tmp_path, document, message):
    path = tmp_path / "arm.json"
    if document is not None:
        path.write_text(document)
    with pytest.raises(SettingsError, match=message):
        load_calibration(path)


def test_file_must_cover_the_bus(tmp_path):
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(LEROBOT_FILE))
    with pytest.raises(SettingsError, match=r"has no entry for elbow_flex$"):
        calibration_for_bus(path, ["shoulder_pan", "elbow_flex"], [1, 3])
    with pytest.raises(SettingsError, match=r"shoulder_pan has id 1, the bus uses id 2$"):
        calibration_for_bus(path, ["shoulder_pan"], [2])
