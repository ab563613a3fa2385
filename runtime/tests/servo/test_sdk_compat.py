"""The official Feetech SDK (scservo_sdk) and LeRobot's FeetechMotorsBus, unchanged, against the emulator."""

import pytest
import scservo_sdk as scs
from servo_helpers import SO100_IDS, SO100_JOINTS


def sdk_port(emulator):
    port = scs.PortHandler(str(emulator.link))
    assert port.openPort()
    return port, scs.PacketHandler(0)


def test_sdk_ping_read_and_write(emulators):
    emulator = emulators("ttySDK", ids=[1, 2, 3])
    port, packets = sdk_port(emulator)
    try:
        model, result, error = packets.ping(port, 2)
        assert (model, result, error) == (777, scs.COMM_SUCCESS, 0)
        assert packets.ping(port, 7)[1] == scs.COMM_RX_TIMEOUT
        emulator.move_by_hand(3, 1304)
        assert packets.read2ByteTxRx(port, 3, 56) == (1304, scs.COMM_SUCCESS, 0)
        assert packets.write1ByteTxRx(port, 3, 41, 30) == (scs.COMM_SUCCESS, 0)
        assert emulator.read_register(3, "Acceleration") == 30
        assert packets.write2ByteTxRx(port, 1, 42, 3000) == (scs.COMM_SUCCESS, 0)
        assert emulator.read_register(1, "Goal_Position") == 3000
        assert packets.read1ByteTxRx(port, 2, 5) == (2, scs.COMM_SUCCESS, 0)
    finally:
        port.closePort()


def test_sdk_group_sync_read_and_write(emulators):
    emulator = emulators("ttySDKGROUP", ids=[1, 2, 3])
    for servo_id, ticks in ((1, 100), (2, 2000), (3, 4000)):
        emulator.move_by_hand(servo_id, ticks)
    port, packets = sdk_port(emulator)
    try:
        reader = scs.GroupSyncRead(port, packets, 56, 2)
        for servo_id in (1, 2, 3):
            assert reader.addParam(servo_id)
        assert reader.txRxPacket() == scs.COMM_SUCCESS
        assert [reader.getData(i, 56, 2) for i in (1, 2, 3)] == [100, 2000, 4000]

        writer = scs.GroupSyncWrite(port, packets, 42, 2)
        for servo_id, goal in ((1, 1111), (2, 2222), (3, 3333)):
            assert writer.addParam(servo_id, [scs.SCS_LOBYTE(goal), scs.SCS_HIBYTE(goal)])
        assert writer.txPacket() == scs.COMM_SUCCESS
        assert emulator.wait_until(lambda: emulator.read_register(3, "Goal_Position") == 3333, 1.0)
        assert [emulator.read_register(i, "Goal_Position") for i in (1, 2, 3)] == [1111, 2222, 3333]
    finally:
        port.closePort()


@pytest.mark.ai  # LeRobot's bus
def test_lerobot_feetech_bus_connects_and_sync_reads(emulators):
    from lerobot.motors import Motor, MotorNormMode  # torch: a second and more, paid only by this test
    from lerobot.motors.feetech import FeetechMotorsBus

    emulator = emulators("ttyLEROBOT", ids=SO100_IDS)
    for servo_id, ticks in zip(SO100_IDS, (1000, 1500, 2000, 2500, 3000, 3500)):
        emulator.move_by_hand(servo_id, ticks)
    motors = {
        name: Motor(servo_id, "sts3215", MotorNormMode.RANGE_M100_100)
        for name, servo_id in zip(SO100_JOINTS, SO100_IDS)
    }
    bus = FeetechMotorsBus(str(emulator.link), motors)
    bus.connect()
    try:
        positions = bus.sync_read("Present_Position", normalize=False)
        assert positions == dict(zip(SO100_JOINTS, (1000, 1500, 2000, 2500, 3000, 3500)))
        bus.write("Homing_Offset", "gripper", -12, normalize=False)
        assert emulator.read_register(6, "Homing_Offset") == -12
        assert bus.read("Homing_Offset", "gripper", normalize=False) == -12
        bus.sync_write("Goal_Position", {"shoulder_pan": 1234, "gripper": 2345}, normalize=False)
        assert emulator.wait_until(lambda: emulator.read_register(6, "Goal_Position") == 2345, 1.0)
        assert emulator.read_register(1, "Goal_Position") == 1234
        assert bus.broadcast_ping() == dict.fromkeys(SO100_IDS, 777)
        bus.enable_torque()
        assert emulator.read_register(1, "Torque_Enable") == 1
    finally:
        bus.disconnect()
    assert [emulator.read_register(i, "Torque_Enable") for i in SO100_IDS] == [0] * 6


def test_sdk_talks_at_another_baud_rate_and_sees_a_shared_id_fail(emulators):
    emulator = emulators("ttySDKBAUD", ids=[1, 1, 2], baud_rate=500_000)
    port, packets = sdk_port(emulator)
    try:
        assert packets.ping(port, 2)[1] == scs.COMM_RX_TIMEOUT  # the SDK opens at 1 Mbaud
        assert port.setBaudRate(500_000)
        assert packets.ping(port, 2) == (777, scs.COMM_SUCCESS, 0)
        assert packets.ping(port, 1)[1] != scs.COMM_SUCCESS
    finally:
        port.closePort()
