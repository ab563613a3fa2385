"""`units: LEROBOT` against LeRobot itself: a pose recorded by this project's recorder holds the values
LeRobot's own SO100Follower reads for that pose on the same (emulated) servo bus.

`joshua-emulate sts3215`'s emulator holds the arm in a pose; LeRobot's SO100Follower, given a
calibration file (one joint in drive mode 1), connects to it and reads its observation; then an
ENCODER_PUBLISHER reads the same bus with the same file and a DATA_SUBSCRIBER records its joint
states with `units: LEROBOT` (and another with LEROBOT_RANGE against `use_degrees=False`).
"""

import json
import signal

import numpy as np
import pytest
from ai_support import NodeProcess, compiled, node_block
from test_ai_recorder import load

from joshua_core import so100

JOINTS = list(so100.SO100_JOINTS)
IDS = [1, 2, 3, 4, 5, 6]
TOPIC = "/follower/joint_states"
CALIBRATION = {  # ranges in ticks, as LeRobot's calibration writes them; elbow_flex mounted reversed
    "shoulder_pan": (0, 800, 1200),
    "shoulder_lift": (0, 900, 3100),
    "elbow_flex": (1, 1000, 3000),
    "wrist_flex": (0, 1100, 3050),
    "wrist_roll": (0, 0, 4095),
    "gripper": (0, 2000, 3200),
}
POSE = {"shoulder_pan": 2500, "shoulder_lift": 1400, "elbow_flex": 2911, "wrist_flex": 2047, "wrist_roll": 333}
POSE["gripper"] = 2480
FIRST_FRAME = "first frame of the episode recorded"
# float32 in the dataset against LeRobot's float64
TOLERANCE = 1e-3


def write_calibration(path) -> None:
    path.write_text(
        json.dumps(
            {
                joint: {"id": i, "drive_mode": mode, "homing_offset": 0, "range_min": low, "range_max": high}
                for (joint, (mode, low, high)), i in zip(CALIBRATION.items(), IDS)
            }
        )
    )


def hold_pose(bus) -> None:
    for joint, servo_id in zip(JOINTS, IDS):
        bus.move_by_hand(servo_id, POSE[joint])


def lerobot_reading(bus, calibration_dir, use_degrees: bool) -> dict:
    """SO100Follower's observation of the pose (it connects without calibrating: the file is given)."""
    from lerobot.robots.so_follower import SO100Follower, SO100FollowerConfig

    robot = SO100Follower(
        SO100FollowerConfig(port=str(bus.link), id="follower", calibration_dir=calibration_dir, use_degrees=use_degrees)
    )
    robot.connect(calibrate=False)
    try:
        robot.bus.disable_torque()  # connecting enabled torque, which moves the arm to its goal
        hold_pose(bus)  # the pose held by hand, as our encoder will read it
        return robot.get_observation()
    finally:
        robot.disconnect()


def recorded(tmp_path, ai_env, bus, calibration, units: str) -> np.ndarray:
    output = tmp_path / units
    settings = compiled(
        "MODE_DATA_COLLECTION",
        node_block(
            "follower",
            "ENCODER_PUBLISHER",
            topic_name=TOPIC,
            serial_port=str(bus.link),
            calibration_file=str(calibration),
            rate_hz=20,
        ),
        node_block(
            "recorder",
            "DATA_SUBSCRIBER",
            topic_name=TOPIC,
            input_topics=[TOPIC],
            output_directory=str(output),
            output_format="parquet",
            rate_hz=10,
            units=units,
            calibration_file=str(calibration),
        ),
    )
    encoder = NodeProcess(settings["follower"], ai_env)
    recorder = NodeProcess(settings["recorder"], ai_env)
    try:
        recorder.wait_for(FIRST_FRAME)
        assert recorder.stop(signal.SIGINT) == 0, recorder.output
        assert encoder.stop(signal.SIGINT) == 0, encoder.output
    finally:
        recorder.kill()
        encoder.kill()
    dataset = load(output)
    assert list(dataset.meta.features["action"]["names"]) == [f"{joint}.pos" for joint in JOINTS]
    return dataset[0]["action"].numpy()


@pytest.mark.parametrize("units, use_degrees", [("LEROBOT", True), ("LEROBOT_RANGE", False)])
def test_a_recorded_pose_holds_what_lerobots_so100_follower_reads(
    units, use_degrees, tmp_path, ai_env, emulators, lerobot_offline
):
    bus = emulators("ttyFOLLOWER", ids=IDS)
    hold_pose(bus)
    calibration = tmp_path / "follower.json"
    write_calibration(calibration)
    reference = lerobot_reading(bus, tmp_path, use_degrees)
    expected = np.array([reference[f"{joint}.pos"] for joint in JOINTS])
    assert np.abs(expected).max() > 1.0  # a pose away from the middle: the test can tell conventions apart

    values = recorded(tmp_path, ai_env, bus, calibration, units)
    assert values == pytest.approx(expected, abs=TOLERANCE), dict(zip(JOINTS, zip(values, expected)))
