"""The STS3215 driver against emulated buses: packets, torque, calibration, retries and reconnects."""

import math

import pytest

from joshua_core.schema import ActionPacket
from joshua_runtime.drivers.calibration import RADIANS_PER_TICK, MotorCalibration
from joshua_runtime.drivers.sts3215 import Sts3215Driver
from joshua_runtime.errors import DeviceError

NAMES = ["a", "b", "c"]


def open_driver(emulator, ids=(1, 2, 3), **options) -> Sts3215Driver:
    driver = Sts3215Driver(str(emulator.link), list(ids), NAMES[: len(ids)], **options)
    driver.open()
    return driver


def test_read_state_gives_calibrated_joint_packets(emulators):
    emulator = emulators("ttyA", ids=[1, 2, 3])
    emulator.move_by_hand(1, 1047)
    emulator.move_by_hand(3, 3047)
    calibration = [
        MotorCalibration(1, 0, 0, 1000, 3000),
        MotorCalibration(2, 0, 0, 0, 4095),
        MotorCalibration(3, 1, 0, 2000, 4000),
    ]
    with Sts3215Driver(str(emulator.link), [1, 2, 3], NAMES, calibration=calibration) as driver:
        packet = driver.read_state()
    state = packet.position
    assert list(state.name) == NAMES
    assert state.position[0] == pytest.approx((1047 - 2000) * RADIANS_PER_TICK)
    assert state.position[1] == pytest.approx(0.5 * RADIANS_PER_TICK)
    assert state.position[2] == pytest.approx(-(3047 - 3000) * RADIANS_PER_TICK)
    assert list(state.effort) == [0.0, 0.0, 0.0]
    assert packet.timestamp.seconds > 0


def test_open_stores_the_calibration_in_the_servos(emulators):
    emulator = emulators("ttyCAL", ids=[1, 2])
    calibration = [MotorCalibration(1, 0, -30, 500, 3500), MotorCalibration(2, 0, 0, 0, 4095)]
    with Sts3215Driver(str(emulator.link), [1, 2], NAMES[:2], calibration=calibration):
        pass
    assert emulator.read_register(1, "Homing_Offset") == -30
    assert emulator.read_register(1, "Min_Position_Limit") == 500
    assert emulator.read_register(1, "Max_Position_Limit") == 3500
    assert emulator.position(1) == 2078  # present = actual - offset
    assert emulator.read_register(1, "Lock") == 1


def test_write_action_clamps_goals_to_the_calibrated_range(emulators):
    emulator = emulators("ttyACT", ids=[1, 2, 3])
    calibration = [MotorCalibration(i, 0, 0, 1000, 3000) for i in (1, 2, 3)]
    with Sts3215Driver(str(emulator.link), [1, 2, 3], NAMES, calibration=calibration) as driver:
        driver.enable_torque()
        action = ActionPacket()
        action.position.extend([0.5, 100.0, math.nan])
        action.speed.extend([1.0, 0.0, 0.0])
        driver.write_action(action)
        assert emulator.wait_until(lambda: emulator.read_register(2, "Goal_Position") == 3000, 1.0)
        assert emulator.read_register(1, "Goal_Position") == round(2000 + 0.5 / RADIANS_PER_TICK)
        assert emulator.read_register(3, "Goal_Position") == 2048  # NaN: held where enable_torque put it
        assert emulator.read_register(1, "Goal_Velocity") == round(1.0 / RADIANS_PER_TICK)
        with pytest.raises(ValueError, match="Goal_Position command has 2 values for 3 joints"):
            short = ActionPacket()
            short.position.extend([0.0, 0.0])
            driver.write_action(short)


def test_torque_enable_holds_the_present_pose_and_disable_releases(emulators):
    emulator = emulators("ttyTQ", ids=[1, 2])
    emulator.write_register(1, "Goal_Position", 100)  # a stale goal must not make the arm jump
    emulator.move_by_hand(1, 2600)
    with open_driver(emulator, ids=(1, 2)) as driver:
        driver.enable_torque()
        assert driver.torque_enabled() == {1: True, 2: True}
        assert emulator.read_register(1, "Goal_Position") == 2600
        driver.disable_torque()
        assert emulator.wait_until(lambda: emulator.read_register(2, "Torque_Enable") == 0, 1.0)
        assert driver.torque_enabled() == {1: False, 2: False}


def test_registers_and_sync_read(emulators):
    emulator = emulators("ttyREG", ids=[1, 2, 3])
    with open_driver(emulator) as driver:
        assert driver.ping(2) == 777
        driver.write(2, "Homing_Offset", -7)
        assert driver.read(2, "Homing_Offset") == -7
        emulator.move_by_hand(3, 10)
        assert driver.sync_read("Present_Position", [3, 1]) == {3: 10, 1: 2048}
        driver.sync_write("Acceleration", {1: 5, 3: 6})
        assert driver.sync_read("Acceleration") == {1: 5, 2: 0, 3: 6}


def test_writes_without_status_packets_when_the_servo_sends_none(emulators):
    emulator = emulators("ttyLVL", ids=[1])
    emulator.write_register(1, "Response_Status_Level", 0)
    with open_driver(emulator, ids=(1,)) as driver:
        driver.write(1, "Acceleration", 9)
        assert driver.read(1, "Acceleration") == 9
        assert driver.transport.stats["timeouts"] == 0


def test_dropped_replies_are_retried(emulators):
    emulator = emulators("ttyDROP", ids=[1, 2, 3])
    with open_driver(emulator) as driver:
        emulator.drop_next_replies(4)  # the 3 replies of one attempt, then the first of the next
        state = driver.read_raw_state()
        assert state == dict.fromkeys([1, 2, 3], (2048, 0, 0))
        assert driver.transport.stats["timeouts"] == 2
        assert driver.transport.stats["retries"] == 2


def test_seeded_random_faults_are_ridden_out(emulators):
    emulator = emulators("ttyNOISY", ids=[1, 2, 3], drop_rate=0.05, corrupt_rate=0.05, seed=3)
    with open_driver(emulator) as driver:
        for _ in range(40):
            assert driver.sync_read("Present_Position") == dict.fromkeys([1, 2, 3], 2048)
    assert emulator.stats["dropped"] + emulator.stats["corrupted"] > 0
    assert driver.transport.stats["retries"] > 0


def test_bad_checksums_are_detected_and_retried(emulators):
    emulator = emulators("ttyCRC", ids=[1, 2, 3])
    with open_driver(emulator) as driver:
        emulator.corrupt_next_replies(1)
        assert driver.read(2, "Model_Number") == 777
        assert driver.transport.stats["checksum_errors"] == 1
        emulator.corrupt_next_replies(10)
        with pytest.raises(DeviceError, match=r"ttyCRC: corrupt replies from servo id 3 after 4 attempts$"):
            driver.read(3, "ID")


def test_missing_port(tmp_path):
    driver = Sts3215Driver(str(tmp_path / "ttyNONE"), [1])
    with pytest.raises(DeviceError, match=r"^serial port .*ttyNONE not found$"):
        driver.open()


def test_missing_servos_are_named(emulators):
    emulator = emulators("ttyMISS", ids=[1, 3])
    driver = Sts3215Driver(str(emulator.link), [1, 2, 3, 4], ["a", "b", "c", "d"])
    with pytest.raises(DeviceError, match=r"ttyMISS: no answer from servo id 2, 4$"):
        driver.open()
    assert not driver.is_open


def test_wrong_model_is_refused(emulators):
    emulator = emulators("ttySCS", ids=[1], model_number=1284)
    with pytest.raises(DeviceError, match=r"servo id 1 is model 1284, expected STS3215 \(777\)$"):
        open_driver(emulator, ids=(1,))


def test_port_disappearing_raises_then_reconnects(emulators):
    emulator = emulators("ttyGONE", ids=[1, 2, 3])
    driver = open_driver(emulator)
    try:
        emulator.move_by_hand(2, 3000)
        emulator.stop()
        with pytest.raises(DeviceError, match=r"ttyGONE disconnected: .*Input/output error$"):
            driver.read_raw_state()
        assert not driver.is_open
        with pytest.raises(DeviceError, match=r"ttyGONE not found$"):
            driver.read_raw_state()
        emulator.start()
        assert driver.read_raw_state()[2] == (3000, 0, 0)
        assert driver.connections == 2
    finally:
        driver.close()


def test_preset_commands_switch_torque(emulators):
    emulator = emulators("ttyPRESET", ids=[1, 2])
    with open_driver(emulator, ids=(1, 2)) as driver:
        action = ActionPacket(preset_commands=["torque_on"])
        action.torque.extend([0.5, 1.5])
        driver.write_action(action)
        assert driver.torque_enabled() == {1: True, 2: True}
        assert driver.sync_read("Torque_Limit") == {1: 500, 2: 1000}
        driver.write_action(ActionPacket(preset_commands=["torque_off"]))
        assert driver.torque_enabled() == {1: False, 2: False}
        with pytest.raises(ValueError, match="unknown preset command 'dance'"):
            driver.write_action(ActionPacket(preset_commands=["dance"]))
