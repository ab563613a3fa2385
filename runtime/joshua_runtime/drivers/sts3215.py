"""Feetech STS3215 bus driver: reads joint states as PerceptionPacket, drives goals from ActionPacket.

    with Sts3215Driver("/dev/ttyUSB0", [1, 2, 3, 4, 5, 6], joint_names) as bus:
        state = bus.read_state()            # one SYNC_READ of position, velocity and load
        bus.enable_torque()                 # holds the present pose first
        bus.write_action(action)            # one SYNC_WRITE of Goal_Position

open() pings every servo and checks its model number (777), and with a calibration file writes the
file's Homing_Offset and position limits into servos that differ (as LeRobot does). After the port
disappears, the next call reopens it and checks the servos again, raising DeviceError while it is gone.
"""

import math

from joshua_core.devices import STS3215_DEFAULT_BAUD_RATE
from joshua_core.schema import ActionPacket, PerceptionPacket
from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.calibration import MotorCalibration, uncalibrated
from joshua_runtime.drivers.driver import Driver
from joshua_runtime.drivers.sts3215_table import (
    MODEL_NUMBER_STS3215,
    STATE_BLOCK_ADDRESS,
    STATE_BLOCK_SIZE,
    decode_value,
    encode_value,
    register,
)
from joshua_runtime.drivers.sts3215_transport import MAX_RETRIES, REPLY_TIMEOUT_S, Expected, SerialTransport
from joshua_runtime.errors import DeviceError

DEFAULT_BAUD_RATE = STS3215_DEFAULT_BAUD_RATE
IDENTITY_BLOCK = (3, 6)  # Model_Number .. Response_Status_Level in one READ
LOAD_FULL_SCALE = 1000.0  # Present_Load / Torque_Limit unit: 0.1 % of max torque
CALIBRATION_REGISTERS = ("Homing_Offset", "Min_Position_Limit", "Max_Position_Limit")
PRESET_TORQUE_ON = "torque_on"
PRESET_TORQUE_OFF = "torque_off"


class Sts3215Driver(Driver):
    """One serial bus of STS3215 servos, listed by id in joint order."""

    def __init__(
        self,
        port: str,
        ids: list[int],
        joint_names: list[str] | None = None,
        *,
        baud_rate: int = DEFAULT_BAUD_RATE,
        calibration: list[MotorCalibration] | None = None,
        reply_timeout_s: float = REPLY_TIMEOUT_S,
        max_retries: int = MAX_RETRIES,
    ):
        self.port = port
        self.ids = list(ids)
        self.joint_names = list(joint_names) if joint_names else [f"joint_{i}" for i in self.ids]
        if len(self.joint_names) != len(self.ids):
            raise ValueError("joint_names and ids differ in length")
        self.calibrated = calibration is not None
        self.calibration = list(calibration) if calibration else [uncalibrated(i) for i in self.ids]
        self.transport = SerialTransport(port, baud_rate, reply_timeout_s, max_retries)
        self._acknowledges: dict[int, bool] = {}
        self.connections = 0  # successful opens so far; grows on every reconnect

    # --- connection ------------------------------------------------------------------------
    def open(self, list_every_missing: bool = True) -> None:
        """Open the port and check every servo; DeviceError names the missing or wrong ones.

        With list_every_missing False (used when reconnecting) the check stops at the first servo
        that does not answer, to keep a failing attempt short.
        """
        self.transport.open()
        try:
            self._check_servos(list_every_missing)
            if self.calibrated:
                self._store_calibration()
        except BaseException:
            self.transport.close()
            raise
        self.connections += 1

    def close(self) -> None:
        self.transport.close()

    def reconnect(self) -> None:
        self.close()
        self.open()

    @property
    def is_open(self) -> bool:
        return self.transport.is_open

    def _ensure_open(self) -> None:
        if not self.transport.is_open:
            self.open(list_every_missing=False)

    def _check_servos(self, list_every_missing: bool) -> None:
        missing, wrong = [], []
        for servo_id in self.ids:
            try:
                self.transport.transact(proto.encode(servo_id, proto.INST_PING), [Expected(servo_id, 0)])
                address, size = IDENTITY_BLOCK
                data = self._read_block(servo_id, address, size)
            except DeviceError:
                if not self.transport.is_open:
                    raise
                missing.append(servo_id)
                if not list_every_missing:
                    break
                continue
            model = int.from_bytes(data[0:2], "little")
            if model != MODEL_NUMBER_STS3215:
                wrong.append(f"servo id {servo_id} is model {model}, expected STS3215 ({MODEL_NUMBER_STS3215})")
            self._acknowledges[servo_id] = data[5] >= 1
        if missing:
            listed = ", ".join(map(str, missing))
            raise DeviceError(f"{self.port}: no answer from servo id {listed}")
        if wrong:
            raise DeviceError(f"{self.port}: {'; '.join(wrong)}")

    def _store_calibration(self) -> None:
        """Write Homing_Offset and position limits from the calibration into servos that differ."""
        for servo_id, motor in zip(self.ids, self.calibration):
            wanted = {
                "Homing_Offset": motor.homing_offset,
                "Min_Position_Limit": motor.range_min,
                "Max_Position_Limit": motor.range_max,
            }
            present = {name: self.read(servo_id, name) for name in CALIBRATION_REGISTERS}
            if present == wanted:
                continue
            self.write(servo_id, "Torque_Enable", 0)
            self.write(servo_id, "Lock", 0)
            for name, value in wanted.items():
                self.write(servo_id, name, value)
            self.write(servo_id, "Lock", 1)

    # --- registers -------------------------------------------------------------------------
    def ping(self, servo_id: int) -> int:
        """The servo's model number."""
        self._ensure_open()
        self.transport.transact(proto.encode(servo_id, proto.INST_PING), [Expected(servo_id, 0)])
        return self.read(servo_id, "Model_Number")

    def _read_block(self, servo_id: int, address: int, size: int) -> bytes:
        packet = proto.encode(servo_id, proto.INST_READ, bytes([address, size]))
        return self.transport.transact(packet, [Expected(servo_id, size)])[0].params

    def read_bytes(self, servo_id: int, address: int, size: int) -> bytes:
        """READ `size` raw bytes of the control table from `address`."""
        self._ensure_open()
        return self._read_block(servo_id, address, size)

    def read(self, servo_id: int, name: str) -> int:
        self._ensure_open()
        reg = register(name)
        return decode_value(reg, self._read_block(servo_id, reg.address, reg.size))

    def write(self, servo_id: int, name: str, value: int) -> None:
        """WRITE one register, waiting for the status packet when the servo sends one."""
        self._ensure_open()
        reg = register(name)
        packet = proto.encode(servo_id, proto.INST_WRITE, bytes([reg.address]) + encode_value(reg, value))
        if self._acknowledges.get(servo_id, True):
            self.transport.transact(packet, [Expected(servo_id, 0)])
        else:
            self.transport.send(packet)

    def sync_read(self, name: str, ids: list[int] | None = None) -> dict[int, int]:
        self._ensure_open()
        reg = register(name)
        ids = self.ids if ids is None else list(ids)
        packets = self._sync_read_block(reg.address, reg.size, ids)
        return {p.servo_id: decode_value(reg, p.params) for p in packets}

    def sync_read_bytes(self, address: int, size: int, ids: list[int]) -> dict[int, bytes]:
        """SYNC_READ `size` raw bytes from `address` of each servo in `ids`."""
        self._ensure_open()
        return {p.servo_id: p.params for p in self._sync_read_block(address, size, list(ids))}

    def _sync_read_block(self, address: int, size: int, ids: list[int]) -> list[proto.Packet]:
        request = proto.encode_sync_read(address, size, ids)
        return self.transport.transact(request, [Expected(servo_id, size) for servo_id in ids])

    def sync_write(self, name: str, values: dict[int, int]) -> None:
        """SYNC_WRITE one register on several servos (never answered)."""
        if not values:
            return
        self._ensure_open()
        reg = register(name)
        data = {servo_id: encode_value(reg, value) for servo_id, value in values.items()}
        self.transport.send(proto.encode_sync_write(reg.address, reg.size, data))

    # --- torque ----------------------------------------------------------------------------
    def enable_torque(self, ids: list[int] | None = None) -> None:
        """Hold the present pose (goal = present position), then switch torque on."""
        ids = self.ids if ids is None else list(ids)
        present = self.sync_read("Present_Position", ids)
        self.sync_write("Goal_Position", present)
        self.sync_write("Torque_Enable", dict.fromkeys(ids, 1))

    def disable_torque(self, ids: list[int] | None = None) -> None:
        ids = self.ids if ids is None else list(ids)
        self.sync_write("Torque_Enable", dict.fromkeys(ids, 0))

    def torque_enabled(self) -> dict[int, bool]:
        return {servo_id: bool(value) for servo_id, value in self.sync_read("Torque_Enable").items()}

    # --- packets ---------------------------------------------------------------------------
    def read_raw_state(self) -> dict[int, tuple[int, int, int]]:
        """Per servo id: (position ticks, velocity ticks/s, load in 0.1 %)."""
        self._ensure_open()
        packets = self._sync_read_block(STATE_BLOCK_ADDRESS, STATE_BLOCK_SIZE, self.ids)
        position, velocity, load = (register(n) for n in ("Present_Position", "Present_Velocity", "Present_Load"))
        return {
            p.servo_id: (
                decode_value(position, p.params[0:2]),
                decode_value(velocity, p.params[2:4]),
                decode_value(load, p.params[4:6]),
            )
            for p in packets
        }

    def read_state(self) -> PerceptionPacket:
        """Joint positions (rad), velocities (rad/s) and efforts (fraction of max torque, signed)."""
        raw = self.read_raw_state()
        packet = PerceptionPacket()
        packet.timestamp.GetCurrentTime()
        state = packet.position
        state.name.extend(self.joint_names)
        for servo_id, motor in zip(self.ids, self.calibration):
            ticks, speed, load = raw[servo_id]
            state.position.append(motor.to_radians(ticks))
            state.velocity.append(motor.speed_to_radians(speed))
            state.effort.append(motor.sign * load / LOAD_FULL_SCALE)
        return packet

    def write_action(self, action: ActionPacket) -> None:
        """Goal positions (rad; NaN leaves a joint alone), optional speed (rad/s) and torque (0-1)."""
        for command in action.preset_commands:
            if command == PRESET_TORQUE_ON:
                self.enable_torque()
            elif command == PRESET_TORQUE_OFF:
                self.disable_torque()
            else:
                raise ValueError(f"unknown preset command {command!r}")
        self._write_per_joint("Torque_Limit", action.torque, _torque_limit)
        self._write_per_joint("Goal_Velocity", action.speed, MotorCalibration.speed_to_ticks)
        self._write_per_joint("Goal_Position", action.position, MotorCalibration.to_ticks)

    def _write_per_joint(self, name: str, values, convert) -> None:
        if not values:
            return
        if len(values) != len(self.ids):
            raise ValueError(f"{name} command has {len(values)} values for {len(self.ids)} joints")
        raw = {
            servo_id: convert(motor, value)
            for servo_id, motor, value in zip(self.ids, self.calibration, values)
            if not math.isnan(value)
        }
        self.sync_write(name, raw)


def _torque_limit(_motor: MotorCalibration, fraction: float) -> int:
    """Torque_Limit register value for a fraction (0-1) of the maximum torque."""
    return round(min(max(fraction, 0.0), 1.0) * LOAD_FULL_SCALE)
