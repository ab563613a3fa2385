"""The guided calibration against emulated arms: the same pose reads the same through our driver and LeRobot's."""

import json
import math
import subprocess
import sys
import time

import pytest
from servo_helpers import SO100_IDS, SO100_JOINTS

from joshua_runtime.drivers.calibration import calibration_for_bus, save_calibration
from joshua_runtime.drivers.sts3215 import Sts3215Driver
from joshua_runtime.servo_tools.bus import open_bus
from joshua_runtime.servo_tools.calibration_flow import (
    ARMS,
    CalibrationError,
    CalibrationFlow,
)

# Encoder ticks each arm reads at a joint's homing pose: the horns of the two arms sit differently.
MOUNTS = {"follower": [300, 3700, 1500, 60, 2900, 1000], "leader": [2900, 400, 100, 3000, 4000, 2047]}
# End stops of each joint in ticks from its homing pose (wrist_roll turns freely; the gripper homes closed).
STOPS = {
    "shoulder_pan": (-1200, 1250),
    "shoulder_lift": (-1100, 1000),
    "elbow_flex": (-1050, 1100),
    "wrist_flex": (-1000, 1080),
    "wrist_roll": (-1800, 1800),
    "gripper": (-15, 1150),
}
POSE = {
    "shoulder_pan": 400,
    "shoulder_lift": -700,
    "elbow_flex": 950,
    "wrist_flex": -30,
    "wrist_roll": 1234,
    "gripper": 600,
}
SWEEP_STEP_TICKS = 150
LEROBOT_CONNECT_ATTEMPTS = 3
HOLD_S = 0.5  # how long the simulated person holds a joint for the terminal's 20 Hz sampling to see it


class Person:
    """Moves one emulated arm by its physical joint angles (ticks from each joint's homing pose)."""

    def __init__(self, emulator, mounts):
        self.emulator, self.mounts = emulator, dict(zip(SO100_JOINTS, mounts))

    def put(self, joint, ticks_from_home):
        servo_id = SO100_IDS[SO100_JOINTS.index(joint)]
        self.emulator.turn_shaft(servo_id, (self.mounts[joint] + ticks_from_home) % 4096)

    def sweep(self, joint, flow):
        low, high = STOPS[joint]
        for ticks in [*range(0, low, -SWEEP_STEP_TICKS), low, *range(low, high, SWEEP_STEP_TICKS), high]:
            self.put(joint, ticks)
            flow.sample(joint)


def calibrate_arm(emulator, role, path):
    person = Person(emulator, MOUNTS[role])
    with open_bus(str(emulator.link), ids=SO100_IDS) as bus:
        flow = CalibrationFlow(bus, ARMS["so100"])
        flow.start()
        for joint in SO100_JOINTS:
            person.put(joint, 0)
            flow.home(joint)
            if joint != "wrist_roll":
                person.sweep(joint, flow)
        save_calibration(path, flow.finish())
    return person


def read_ours(emulator, path):
    calibration = calibration_for_bus(path, SO100_JOINTS, SO100_IDS)
    with Sts3215Driver(str(emulator.link), SO100_IDS, SO100_JOINTS, calibration=calibration) as bus:
        state = bus.read_state().position
        return dict(zip(state.name, (math.degrees(radians) for radians in state.position)))


def read_lerobot(emulator, path):
    from lerobot.motors import Motor, MotorNormMode  # torch: a second and more, paid only by the test using it
    from lerobot.motors import MotorCalibration as LeRobotCalibration
    from lerobot.motors.feetech import FeetechMotorsBus

    calibration = {name: LeRobotCalibration(**entry) for name, entry in json.loads(path.read_text()).items()}
    motors = {name: Motor(i, "sts3215", MotorNormMode.DEGREES) for name, i in zip(SO100_JOINTS, SO100_IDS)}
    bus = FeetechMotorsBus(str(emulator.link), motors, calibration=calibration)
    for attempt in range(LEROBOT_CONNECT_ATTEMPTS):  # its broadcast PING has a tight timeout on a loaded machine
        try:
            bus.connect()
            break
        except RuntimeError:
            if bus.port_handler.is_open:
                bus.port_handler.closePort()
            if attempt == LEROBOT_CONNECT_ATTEMPTS - 1:
                raise
    try:
        assert bus.is_calibrated  # the registers our flow wrote are the ones LeRobot expects
        return bus.sync_read("Present_Position"), bus.sync_read("Present_Position", normalize=False)
    finally:
        bus.disconnect(disable_torque=False)


@pytest.mark.ai  # LeRobot's bus
def test_same_pose_reads_the_same_on_both_arms_through_both_stacks(emulators, tmp_path):
    readings, raw = {}, {}
    for role in ("follower", "leader"):
        emulator = emulators(f"tty{role.upper()}", ids=SO100_IDS)
        path = tmp_path / f"so100_{role}.json"
        person = calibrate_arm(emulator, role, path)
        for joint, ticks in POSE.items():
            person.put(joint, ticks)
        ours, (lerobot, raw[role]) = read_ours(emulator, path), read_lerobot(emulator, path)
        assert ours == pytest.approx(lerobot, abs=1e-9)
        readings[role] = ours
        saved = json.loads(path.read_text())
        assert saved["wrist_roll"]["range_min"] == 0 and saved["wrist_roll"]["range_max"] == 4095
        assert saved["shoulder_pan"]["range_max"] - saved["shoulder_pan"]["range_min"] == 2450
    offsets = {role: json.loads((tmp_path / f"so100_{role}.json").read_text()) for role in readings}
    assert offsets["follower"]["elbow_flex"]["homing_offset"] != offsets["leader"]["elbow_flex"]["homing_offset"]
    assert readings["follower"] == pytest.approx(readings["leader"], abs=1e-9)
    assert raw["follower"] == raw["leader"]  # so every LeRobot normalisation (RANGE_M100_100 too) agrees
    for joint in SO100_JOINTS:
        follower, leader = offsets["follower"][joint], offsets["leader"][joint]
        assert (follower["range_min"], follower["range_max"]) == (leader["range_min"], leader["range_max"])
    assert readings["follower"]["wrist_roll"] == pytest.approx((1234 - 0.5) * 360 / 4095)


def test_a_sweep_across_the_wrap_point_is_refused(emulators):
    emulator = emulators("ttyWRAP", ids=SO100_IDS)
    person = Person(emulator, MOUNTS["follower"])
    with open_bus(str(emulator.link), ids=SO100_IDS) as bus:
        flow = CalibrationFlow(bus, ARMS["so100"])
        flow.start()
        person.put("elbow_flex", 0)
        flow.home("elbow_flex")
        for ticks in range(0, 2300, SWEEP_STEP_TICKS):
            person.put("elbow_flex", ticks)
            flow.sample("elbow_flex")
        with pytest.raises(CalibrationError, match="elbow_flex crossed the encoder's wrap point"):
            flow.calibration_of("elbow_flex")
        with pytest.raises(CalibrationError, match="shoulder_pan was never homed"):
            flow.result()


@pytest.mark.process
def test_terminal_calibration_driven_through_stdin(emulators, tmp_path):
    emulator = emulators("ttyTERMINAL", ids=SO100_IDS)
    person = Person(emulator, MOUNTS["leader"])
    output = tmp_path / "leader.json"
    command = [
        sys.executable,
        "-m",
        "joshua_runtime.servo_tools.cli",
        "calibrate",
        str(emulator.link),
        "--role",
        "leader",
        "--output",
        str(output),
    ]
    process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    transcript = []
    try:
        for line in process.stdout:
            transcript.append(line.rstrip())
            joint = line.split()[1] if line.startswith(("Hold", "Move")) else None
            if line.startswith("Hold"):
                person.put(joint, 0)
            elif line.startswith("Move"):
                low, high = STOPS[joint]
                person.put(joint, low)
                time.sleep(HOLD_S)
                person.put(joint, high)
            else:
                continue
            process.stdin.write("\n")
            process.stdin.flush()
    finally:
        process.stdin.close()
        assert process.wait(30) == 0, transcript
    assert (
        transcript[0]
        == "Hold shoulder_pan at its homing pose: arm pointing straight ahead over the front of the base. Press Enter."
    )
    assert "wrist_roll turns freely: its range is the full turn, no sweep needed." in transcript
    assert transcript[-1] == f"calibration written to {output}"
    saved = json.loads(output.read_text())
    for joint, (low, high) in STOPS.items():
        if joint != "wrist_roll":
            assert (saved[joint]["range_min"], saved[joint]["range_max"]) == (2047 + low, 2047 + high), joint
    rejected = subprocess.run(command, capture_output=True, text=True, check=False)
    assert rejected.returncode == 2
    assert rejected.stderr == f"joshua-servo: error: {output} exists; pass --force to replace it\n"
