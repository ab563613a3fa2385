"""One emulated STS3215 servo: control table memory, instruction semantics and first-order motion.

Positions are kept in the servo's own frame (Present_Position = actual - Homing_Offset), so writing
Homing_Offset shifts the reported position the way the real firmware does. With torque on in
position mode the shaft moves toward Goal_Position (clamped to the position limits) at most at
Goal_Velocity (or MAX_SPEED_TICKS_S when 0), slowing exponentially with MOTION_TIME_CONSTANT_S near
the goal. With torque off it stays where it is until moved by hand (`move_by_hand`).
"""

import math

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import (
    BY_NAME,
    EEPROM_END,
    MAX_TICK,
    MODEL_NUMBER_STS3215,
    READ_ONLY_BYTES,
    REGISTERS,
    TABLE_SIZE,
    TICKS_PER_TURN,
    decode_value,
    encode_value,
    register,
)

MOTION_TIME_CONSTANT_S = 0.02
MAX_SPEED_TICKS_S = 3400.0
SETTLED_TICKS = 0.05  # closer than this to the goal counts as arrived
MOVING_THRESHOLD_TICKS = 0.5
LOAD_PER_TICK_OF_ERROR = 4  # 0.1 % of max torque per tick between goal and position
CURRENT_PER_LOAD = 0.4  # Present_Current units (6.5 mA) per Present_Load unit
HAND_VELOCITY_HOLD_S = 0.1  # a hand-moved shaft reports its last speed this long

MODE_POSITION = 0
MODE_SPEED = 1


class EmulatedServo:
    """State of one servo; every method takes the current monotonic time `now` in seconds."""

    def __init__(
        self,
        servo_id: int,
        position: float,
        now: float,
        model_number: int = MODEL_NUMBER_STS3215,
        baud_rate_code: int = 0,
    ):
        self.model_number = model_number
        self.memory = bytearray(TABLE_SIZE)
        self._load_factory_defaults()
        self._set("ID", servo_id)
        self._set("Baud_Rate", baud_rate_code)
        self.saved_eeprom = bytes(self.memory[:EEPROM_END])
        self.position = float(position)
        self.velocity = 0.0
        self._set("Goal_Position", round(position))
        self.injected_errors = 0
        self.registered_write: tuple[int, bytes] | None = None
        self._time = now
        self._hand_velocity = 0.0
        self._hand_time = -math.inf
        self._refresh(now)

    # --- registers -------------------------------------------------------------------------
    @property
    def id(self) -> int:
        return self.memory[BY_NAME["ID"].address]

    def get(self, name: str) -> int:
        reg = register(name)
        return decode_value(reg, self.memory[reg.address : reg.address + reg.size])

    def _set(self, name: str, value: int) -> None:
        reg = register(name)
        self.memory[reg.address : reg.address + reg.size] = encode_value(reg, value)

    def _load_factory_defaults(self) -> None:
        for reg in REGISTERS:
            self._set(reg.name, reg.default)
        self._set("Model_Number", self.model_number)

    def read(self, address: int, size: int, now: float) -> bytes:
        self.advance(now)
        data = bytes(self.memory[address : address + size])
        return data + bytes(size - len(data))

    def write(self, address: int, data: bytes, now: float) -> None:
        """A WRITE from the bus: read-only bytes are ignored, EEPROM persists only when unlocked."""
        self.advance(now)
        old_offset = self.get("Homing_Offset")
        for index, value in enumerate(data):
            target = address + index
            if target < TABLE_SIZE and target not in READ_ONLY_BYTES:
                self.memory[target] = value
        if self.get("Lock") == 0 and address < EEPROM_END:
            self.saved_eeprom = bytes(self.memory[:EEPROM_END])
        new_offset = self.get("Homing_Offset")
        if new_offset != old_offset:
            self.position = (self.position + old_offset - new_offset) % TICKS_PER_TURN
        self._refresh(now)

    # --- instructions ----------------------------------------------------------------------
    def execute(self, instruction: int, params: bytes, now: float) -> bytes | None:
        """Run one addressed instruction; return the status parameters, or None when malformed."""
        if instruction == proto.INST_PING:
            return b""
        if instruction == proto.INST_READ:
            return self.read(params[0], params[1], now) if len(params) >= 2 else None
        if instruction == proto.INST_WRITE:
            if len(params) < 2:
                return None
            self.write(params[0], params[1:], now)
            return b""
        if instruction == proto.INST_REG_WRITE:
            if len(params) < 2:
                return None
            self.registered_write = (params[0], bytes(params[1:]))
            return b""
        if instruction == proto.INST_ACTION:
            if self.registered_write is not None:
                self.write(*self.registered_write, now)
                self.registered_write = None
            return b""
        if instruction in (proto.INST_RESET, proto.INST_RECOVERY):
            self.factory_reset(now)
            return b""
        if instruction == proto.INST_RESTART:
            self.restart(now)
            return b""
        if instruction == proto.INST_CALIBRATE_POSITION:
            self.calibrate_middle(now)
            return b""
        return None

    def factory_reset(self, now: float) -> None:
        """Every register back to its default except the ID; the shaft does not move."""
        self.advance(now)
        servo_id = self.id
        self._load_factory_defaults()
        self._set("ID", servo_id)
        self._set("Goal_Position", round(self.position))
        self.saved_eeprom = bytes(self.memory[:EEPROM_END])
        self._refresh(now)

    def restart(self, now: float) -> None:
        """Power cycle: EEPROM from its saved copy, RAM to defaults, torque off."""
        self.advance(now)
        actual = self.position + self.get("Homing_Offset")
        self._load_factory_defaults()
        self.memory[:EEPROM_END] = self.saved_eeprom
        self.position = (actual - self.get("Homing_Offset")) % TICKS_PER_TURN
        self._set("Goal_Position", round(self.position))
        self.registered_write = None
        self._refresh(now)

    def calibrate_middle(self, now: float) -> None:
        """Position calibration: choose Homing_Offset so the present position reads 2048."""
        self.advance(now)
        offset = self.get("Homing_Offset") + round(self.position) - TICKS_PER_TURN // 2
        offset = (offset + TICKS_PER_TURN // 2) % TICKS_PER_TURN - TICKS_PER_TURN // 2
        self._set("Homing_Offset", offset)
        self.position = float(TICKS_PER_TURN // 2)
        self._refresh(now)

    # --- physics ---------------------------------------------------------------------------
    def move_by_hand(self, position: float, now: float) -> None:
        """Put the shaft at `position` (present-position frame), as a hand moving the arm would."""
        self.advance(now)
        elapsed = now - self._hand_time
        self._hand_velocity = (position - self.position) / elapsed if 0 < elapsed < HAND_VELOCITY_HOLD_S else 0.0
        self._hand_time = now
        self.position = min(max(float(position), 0.0), float(MAX_TICK))
        self._refresh(now)

    def target(self) -> float:
        goal = self.get("Goal_Position")
        low, high = self.get("Min_Position_Limit"), self.get("Max_Position_Limit")
        if low < high:
            goal = min(max(goal, low), high)
        return float(min(max(goal, 0), MAX_TICK))

    def advance(self, now: float) -> None:
        """Move the shaft for the time elapsed since the last call."""
        dt = now - self._time
        if dt <= 0:
            return
        self._time = now
        torque_on = self.get("Torque_Enable") == 1
        mode = self.get("Operating_Mode")
        if torque_on and mode == MODE_POSITION:
            self._approach_goal(dt)
        elif torque_on and mode == MODE_SPEED:
            self.velocity = float(self.get("Goal_Velocity"))
            self.position = (self.position + self.velocity * dt) % TICKS_PER_TURN
        else:
            held = now - self._hand_time < HAND_VELOCITY_HOLD_S
            self.velocity = self._hand_velocity if held else 0.0
        self._refresh(now)

    def _approach_goal(self, dt: float) -> None:
        target = self.target()
        max_speed = abs(self.get("Goal_Velocity")) or MAX_SPEED_TICKS_S
        distance = target - self.position
        knee = max_speed * MOTION_TIME_CONSTANT_S  # below this distance the motion is exponential
        remaining = dt
        self.velocity = 0.0
        if abs(distance) > knee:
            saturated_s = (abs(distance) - knee) / max_speed
            step = max_speed * min(saturated_s, remaining)
            self.position += math.copysign(step, distance)
            self.velocity = math.copysign(max_speed, distance)
            remaining -= min(saturated_s, remaining)
        if remaining > 0:
            left = (target - self.position) * math.exp(-remaining / MOTION_TIME_CONSTANT_S)
            self.position = target - left
            self.velocity = left / MOTION_TIME_CONSTANT_S
        if abs(target - self.position) < SETTLED_TICKS:
            self.position, self.velocity = target, 0.0

    def _refresh(self, now: float) -> None:
        """Write the present-state registers from the physical state."""
        torque_on = self.get("Torque_Enable") == 1
        error = self.target() - self.position if torque_on else 0.0
        load = max(-1000, min(1000, round(error * LOAD_PER_TICK_OF_ERROR)))
        self._set("Present_Position", min(max(round(self.position), 0), MAX_TICK))
        self._set("Present_Velocity", round(self.velocity))
        self._set("Present_Load", load)
        self._set("Present_Current", round(abs(load) * CURRENT_PER_LOAD))
        moving = abs(self.velocity) > MOVING_THRESHOLD_TICKS or abs(error) > MOVING_THRESHOLD_TICKS
        self._set("Moving", int(moving))
        self._set("Status", self._status_bits())

    def _status_bits(self) -> int:
        bits = self.injected_errors
        voltage = self.get("Present_Voltage")
        if not self.get("Min_Voltage_Limit") <= voltage <= self.get("Max_Voltage_Limit"):
            bits |= proto.ERROR_VOLTAGE
        if self.get("Present_Temperature") > self.get("Max_Temperature_Limit"):
            bits |= proto.ERROR_OVERHEAT
        return bits & 0x7F

    def set_sensor(self, name: str, value: int, now: float) -> None:
        """Set a read-only sensor register (Present_Voltage, Present_Temperature) for a test."""
        self.advance(now)
        self._set(name, value)
        self._refresh(now)

    def inject_errors(self, bits: int, now: float) -> None:
        self.advance(now)
        self.injected_errors = bits
        self._refresh(now)

    def error_byte(self) -> int:
        return self.get("Status")
