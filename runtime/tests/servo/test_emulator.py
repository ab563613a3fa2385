"""The STS3215 emulator at the byte level: documented exchanges, broadcast rules, registers, motion, faults."""

import signal
import subprocess
import sys
import time

import pytest
import serial
from servo_helpers import wait_for

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import register

REPLY_WAIT_S = 2.0  # the longest a reply may take on a loaded machine; a reply that comes ends the wait
SILENCE_S = 0.15


class RawPort:
    """A bare serial port on the emulator's link, to send exact bytes and collect what comes back."""

    def __init__(self, link):
        self.serial = serial.Serial(str(link), 1_000_000, timeout=REPLY_WAIT_S)

    def ask(self, packet: bytes, reply_bytes: int) -> bytes:
        self.serial.reset_input_buffer()
        self.serial.write(packet)
        return self.serial.read(reply_bytes)

    def silent_after(self, packet: bytes) -> bool:
        self.serial.reset_input_buffer()
        self.serial.write(packet)
        self.serial.timeout = SILENCE_S
        try:
            return self.serial.read(1) == b""
        finally:
            self.serial.timeout = REPLY_WAIT_S

    def close(self):
        self.serial.close()


@pytest.fixture
def bus(emulators):
    emulator = emulators("ttyEMU", ids=[1, 2, 3])
    port = RawPort(emulator.link)
    yield emulator, port
    port.close()


def read_packet(servo_id, name):
    reg = register(name)
    return proto.encode(servo_id, proto.INST_READ, bytes([reg.address, reg.size]))


def write_packet(servo_id, address, data, instruction=proto.INST_WRITE):
    return proto.encode(servo_id, instruction, bytes([address]) + bytes(data))


def test_documented_ping_and_read(bus):
    emulator, port = bus
    assert port.ask(bytes.fromhex("FF FF 01 02 01 FB"), 6) == bytes.fromhex("FF FF 01 02 00 FC")
    emulator.move_by_hand(1, 1304)
    assert port.ask(bytes.fromhex("FF FF 01 04 02 38 02 BE"), 8) == bytes.fromhex("FF FF 01 04 00 18 05 DD")


def test_documented_sync_read_answers_in_request_order(bus):
    _, port = bus
    request = proto.encode_sync_read(0x38, 8, [2, 1])
    reply = port.ask(request, 28)
    assert reply[:14] == bytes.fromhex("FF FF 02 0A 00 00 08 00 00 00 00 79 1E 54")
    assert reply[14:] == bytes.fromhex("FF FF 01 0A 00 00 08 00 00 00 00 79 1E 55")


def test_model_number_firmware_and_identity(bus):
    _, port = bus
    reply = port.ask(proto.encode(2, proto.INST_READ, bytes([0, 9])), 15)
    assert reply[5:14] == bytes([3, 10, 0, 0x09, 0x03, 2, 0, 0, 1])


def test_only_addressed_servos_answer(bus):
    _, port = bus
    assert port.silent_after(proto.encode(9, proto.INST_PING))
    assert port.silent_after(proto.encode(proto.BROADCAST_ID, proto.INST_READ, bytes([56, 2])))
    assert port.silent_after(write_packet(proto.BROADCAST_ID, 41, [10]))


def test_broadcast_ping_is_answered_by_every_servo(bus):
    _, port = bus
    reply = port.ask(proto.encode(proto.BROADCAST_ID, proto.INST_PING), 18)
    assert reply == b"".join(proto.encode(i, 0) for i in (1, 2, 3))


def test_broadcast_write_reaches_every_servo(bus):
    emulator, port = bus
    assert port.silent_after(write_packet(proto.BROADCAST_ID, register("Acceleration").address, [77]))
    assert [emulator.read_register(i, "Acceleration") for i in (1, 2, 3)] == [77, 77, 77]


def test_response_status_level_zero_answers_only_ping_and_read(bus):
    emulator, port = bus
    assert port.ask(write_packet(1, 8, [0]), 6) == proto.encode(1, 0)
    assert port.silent_after(write_packet(1, 41, [5]))
    assert emulator.read_register(1, "Acceleration") == 5
    assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, 0)
    assert port.ask(read_packet(1, "Acceleration"), 7) == proto.encode(1, 0, b"\x05")


def test_reg_write_waits_for_action(bus):
    emulator, port = bus
    goal = register("Goal_Time").address
    assert port.ask(write_packet(2, goal, [0x34, 0x12], proto.INST_REG_WRITE), 6) == proto.encode(2, 0)
    assert emulator.read_register(2, "Goal_Time") == 0
    assert port.silent_after(proto.encode(proto.BROADCAST_ID, proto.INST_ACTION))
    assert emulator.read_register(2, "Goal_Time") == 0x1234


def test_sync_write_is_silent_and_sign_magnitude_goals_clamp(bus):
    emulator, port = bus
    blocks = {1: (0x8000 | 20).to_bytes(2, "little"), 3: (3000).to_bytes(2, "little")}
    assert port.silent_after(proto.encode_sync_write(register("Goal_Position").address, 2, blocks))
    assert emulator.read_register(1, "Goal_Position") == -20
    assert emulator.read_register(3, "Goal_Position") == 3000
    assert emulator.servo(1).target() == 0.0


def test_read_only_registers_ignore_writes(bus):
    emulator, port = bus
    assert port.ask(write_packet(1, register("Model_Number").address, [1, 1]), 6) == proto.encode(1, 0)
    assert emulator.read_register(1, "Model_Number") == 777


def test_torque_on_moves_toward_the_goal_and_reports_motion(bus):
    emulator, _ = bus
    emulator.write_register(1, "Goal_Position", 2448)
    time.sleep(0.05)
    assert emulator.position(1) == 2048  # torque off: no motion
    emulator.write_register(1, "Torque_Enable", 1)
    assert wait_for(lambda: emulator.read_register(1, "Moving") == 1, 1.0)
    assert emulator.read_register(1, "Present_Velocity") > 0
    assert emulator.read_register(1, "Present_Load") > 0
    assert wait_for(lambda: emulator.read_register(1, "Moving") == 0, 2.0)
    assert emulator.position(1) == 2448
    assert emulator.read_register(1, "Present_Load") == 0


def test_position_limits_bound_the_motion(bus):
    emulator, _ = bus
    emulator.write_register(2, "Max_Position_Limit", 2100)
    emulator.write_register(2, "Torque_Enable", 1)
    emulator.write_register(2, "Goal_Position", 4000)
    assert wait_for(lambda: emulator.position(2) == 2100, 2.0)


def test_homing_offset_shifts_the_present_position(bus):
    emulator, _ = bus
    emulator.write_register(3, "Homing_Offset", -100)
    assert emulator.position(3) == 2148
    emulator.write_register(3, "Homing_Offset", 48)
    assert emulator.position(3) == 2000


def test_position_calibration_instruction_centres_the_present_position(bus):
    emulator, port = bus
    emulator.move_by_hand(2, 2500)
    assert port.ask(proto.encode(2, proto.INST_CALIBRATE_POSITION), 6) == proto.encode(2, 0)
    assert emulator.position(2) == 2048
    assert emulator.read_register(2, "Homing_Offset") == 452


def test_id_change_answers_with_the_old_id_then_the_new(bus):
    emulator, port = bus
    assert port.ask(write_packet(3, register("ID").address, [9]), 6) == proto.encode(3, 0)
    assert port.silent_after(proto.encode(3, proto.INST_PING))
    assert port.ask(proto.encode(9, proto.INST_PING), 6) == proto.encode(9, 0)
    assert emulator.ids == [1, 2, 9]


def test_restart_keeps_only_unlocked_eeprom_writes(bus):
    emulator, port = bus
    emulator.write_register(1, "Max_Position_Limit", 3000)  # Lock defaults to 1: not persisted
    emulator.write_register(2, "Lock", 0)
    emulator.write_register(2, "Max_Position_Limit", 3000)
    emulator.write_register(2, "Torque_Enable", 1)
    for servo_id in (1, 2):
        assert port.silent_after(proto.encode(servo_id, proto.INST_RESTART))
    # Silence is not the restart's end on a loaded machine: the bus answers in order, so a ping answered is.
    assert port.ask(proto.encode(2, proto.INST_PING), 6) == proto.encode(2, 0)
    assert emulator.read_register(1, "Max_Position_Limit") == 4095
    assert emulator.read_register(2, "Max_Position_Limit") == 3000
    assert emulator.read_register(2, "Torque_Enable") == 0


def test_reset_restores_factory_defaults_but_keeps_the_id(bus):
    emulator, port = bus
    emulator.write_register(2, "Acceleration", 50)
    emulator.write_register(2, "Homing_Offset", 10)
    assert port.ask(proto.encode(2, proto.INST_RESET), 6) == proto.encode(2, 0)
    assert emulator.read_register(2, "Acceleration") == 0
    assert emulator.read_register(2, "Homing_Offset") == 0
    assert emulator.read_register(2, "ID") == 2


def test_status_error_bits(bus):
    emulator, port = bus
    emulator.set_sensor(1, "Present_Temperature", 80)
    assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, proto.ERROR_OVERHEAT)
    emulator.set_sensor(1, "Present_Temperature", 30)
    emulator.set_sensor(1, "Present_Voltage", 30)
    emulator.inject_error(1, proto.ERROR_OVERLOAD)
    assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, proto.ERROR_OVERLOAD | proto.ERROR_VOLTAGE)
    assert emulator.read_register(1, "Status") == proto.ERROR_OVERLOAD | proto.ERROR_VOLTAGE


def test_garbage_and_bad_checksums_are_ignored(bus):
    emulator, port = bus
    bad = bytearray(proto.encode(1, proto.INST_PING))
    bad[-1] ^= 1
    assert port.silent_after(bytes(bad))
    reply = port.ask(b"\x00\xff\x42\xff\xff\x05\xff" + proto.encode(2, proto.INST_PING), 6)
    assert reply == proto.encode(2, 0)
    assert emulator.stats["bad_checksums"] >= 1


def test_a_stalled_partial_frame_is_dropped(bus):
    _, port = bus
    port.serial.write(b"\xff\xff\x01\x09\x03")  # promises 9 more bytes that never come
    time.sleep(0.1)
    assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, 0)


def test_forced_and_seeded_faults(emulators):
    emulator = emulators("ttyFAULT", ids=[1], drop_rate=0.5, seed=7)
    port = RawPort(emulator.link)
    ping = proto.encode(1, proto.INST_PING)
    dropped = []
    try:
        for asked in range(1, 21):
            before = emulator.stats["dropped"]
            port.serial.write(ping)
            # Whether this reply is dropped is the emulator's to say, once it has handled the ping; a reply
            # that is sent must then come whole, and a dropped one leaves the wire silent.
            assert emulator.wait_until(lambda asked=asked: emulator.stats["replies"] == asked, REPLY_WAIT_S)
            if emulator.stats["dropped"] > before:
                dropped.append(asked)
                port.serial.timeout = SILENCE_S
                assert port.serial.read(1) == b"", asked
                port.serial.timeout = REPLY_WAIT_S
            else:
                assert port.serial.read(6) == proto.encode(1, 0), asked
    finally:
        port.close()
    assert 0 < len(dropped) < 20
    emulator.drop_rate = 0.0
    emulator.corrupt_next_replies(1)
    port = RawPort(emulator.link)
    try:
        corrupted = port.ask(proto.encode(1, proto.INST_PING), 6)
        assert corrupted[:-1] == proto.encode(1, 0)[:-1] and corrupted[-1] != proto.encode(1, 0)[-1]
        emulator.drop_next_replies(1)
        assert port.silent_after(proto.encode(1, proto.INST_PING))
        assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, 0)
    finally:
        port.close()


@pytest.mark.process
def test_joshua_emulate_command_serves_until_sigint(tmp_path):
    link = tmp_path / "ttyCLI"
    process = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "sts3215", "--ids", "4,5", "--link", str(link)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert wait_for(link.exists, 10.0)
        port = RawPort(link)
        try:
            assert port.ask(proto.encode(5, proto.INST_PING), 6) == proto.encode(5, 0)
        finally:
            port.close()
        process.send_signal(signal.SIGINT)
        stdout, _ = process.communicate(timeout=5)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 0
    assert stdout.startswith(f"sts3215: servos 4,5 on {link} -> /dev/pts/")
    assert not link.exists()


def test_a_servo_hears_only_its_own_baud_rate(emulators):
    emulator = emulators("ttyBAUD", ids=[1, 2])
    emulator.write_register(2, "Baud_Rate", 4)  # 115200
    port = RawPort(emulator.link)
    try:
        assert port.ask(proto.encode(1, proto.INST_PING), 6) == proto.encode(1, 0)
        assert port.silent_after(proto.encode(2, proto.INST_PING))
        port.serial.baudrate = 115_200
        assert port.ask(proto.encode(2, proto.INST_PING), 6) == proto.encode(2, 0)
        assert port.silent_after(proto.encode(1, proto.INST_PING))
    finally:
        port.close()


def test_two_servos_on_one_id_collide_on_the_wire(emulators):
    emulator = emulators("ttyTWIN", ids=[1, 1])
    port = RawPort(emulator.link)
    try:
        wire = port.ask(proto.encode(1, proto.INST_PING), 7)
    finally:
        port.close()
    reply = proto.encode(1, 0)
    assert wire == bytes(a & b for a, b in zip(reply + b"\xff", b"\xff" + reply))
    parser = proto.PacketParser()
    parser.feed(wire)
    assert parser.pop() is None and parser.discarded > 0


def test_turning_a_shaft_reads_through_the_homing_offset(emulators):
    emulator = emulators("ttySHAFT", ids=[1])
    emulator.write_register(1, "Homing_Offset", -300)
    emulator.turn_shaft(1, 4000)
    assert emulator.position(1) == (4000 + 300) % 4096
