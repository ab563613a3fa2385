"""The STS3215 control table: address, size, sign encoding, access and factory default of each register."""

from dataclasses import dataclass

from joshua_core.devices import STS3215_BAUD_RATE_CODES
from joshua_runtime.drivers.sts3215_protocol import from_sign_magnitude, to_sign_magnitude

MODEL_NUMBER_STS3215 = 777
TABLE_SIZE = 128  # bytes of emulated memory; addresses past the last register read as 0
EEPROM_END = 40  # addresses below this are EEPROM (kept across restart when unlocked)
TICKS_PER_TURN = 4096
MAX_TICK = TICKS_PER_TURN - 1
BAUD_RATE_CODES = STS3215_BAUD_RATE_CODES


@dataclass(frozen=True)
class Register:
    name: str
    address: int
    size: int
    default: int = 0
    sign_bit: int | None = None  # sign-magnitude encoding with this sign bit
    writable: bool = True


REGISTERS = [
    Register("Firmware_Major_Version", 0, 1, 3, writable=False),
    Register("Firmware_Minor_Version", 1, 1, 10, writable=False),
    Register("Model_Number", 3, 2, MODEL_NUMBER_STS3215, writable=False),
    Register("ID", 5, 1, 1),
    Register("Baud_Rate", 6, 1, 0),
    Register("Return_Delay_Time", 7, 1, 0),
    Register("Response_Status_Level", 8, 1, 1),
    Register("Min_Position_Limit", 9, 2, 0),
    Register("Max_Position_Limit", 11, 2, MAX_TICK),
    Register("Max_Temperature_Limit", 13, 1, 70),
    Register("Max_Voltage_Limit", 14, 1, 140),
    Register("Min_Voltage_Limit", 15, 1, 40),
    Register("Max_Torque_Limit", 16, 2, 1000),
    Register("Phase", 18, 1, 12),
    Register("Unloading_Condition", 19, 1, 44),
    Register("LED_Alarm_Condition", 20, 1, 47),
    Register("P_Coefficient", 21, 1, 32),
    Register("D_Coefficient", 22, 1, 32),
    Register("I_Coefficient", 23, 1, 0),
    Register("Minimum_Startup_Force", 24, 2, 16),
    Register("CW_Dead_Zone", 26, 1, 1),
    Register("CCW_Dead_Zone", 27, 1, 1),
    Register("Protection_Current", 28, 2, 500),
    Register("Angular_Resolution", 30, 1, 1),
    Register("Homing_Offset", 31, 2, 0, sign_bit=11),
    Register("Operating_Mode", 33, 1, 0),
    Register("Protective_Torque", 34, 1, 20),
    Register("Protection_Time", 35, 1, 200),
    Register("Overload_Torque", 36, 1, 80),
    Register("Torque_Enable", 40, 1, 0),
    Register("Acceleration", 41, 1, 0),
    Register("Goal_Position", 42, 2, 0, sign_bit=15),
    Register("Goal_Time", 44, 2, 0),
    Register("Goal_Velocity", 46, 2, 0, sign_bit=15),
    Register("Torque_Limit", 48, 2, 1000),
    Register("Lock", 55, 1, 1),
    Register("Present_Position", 56, 2, 0, sign_bit=15, writable=False),
    Register("Present_Velocity", 58, 2, 0, sign_bit=15, writable=False),
    Register("Present_Load", 60, 2, 0, sign_bit=10, writable=False),
    Register("Present_Voltage", 62, 1, 121, writable=False),
    Register("Present_Temperature", 63, 1, 30, writable=False),
    Register("Status", 65, 1, 0, writable=False),
    Register("Moving", 66, 1, 0, writable=False),
    Register("Present_Current", 69, 2, 0, writable=False),
]
BY_NAME = {register.name: register for register in REGISTERS}
BY_ADDRESS = {register.address: register for register in REGISTERS}
READ_ONLY_BYTES = frozenset(
    address
    for register in REGISTERS
    if not register.writable
    for address in range(register.address, register.address + register.size)
)

# Block read every control cycle: Present_Position, Present_Velocity, Present_Load.
STATE_BLOCK_ADDRESS = BY_NAME["Present_Position"].address
STATE_BLOCK_SIZE = 6


def register(name_or_address: str | int) -> Register:
    """Look a register up by name (`Goal_Position`) or address (42)."""
    table = BY_NAME if isinstance(name_or_address, str) else BY_ADDRESS
    try:
        return table[name_or_address]
    except KeyError:
        raise KeyError(f"STS3215 has no register {name_or_address!r}") from None


def encode_value(reg: Register, value: int) -> bytes:
    """Little-endian bytes of a register value (sign-magnitude where the register uses it)."""
    raw = int(value)
    if reg.sign_bit is not None:
        raw = to_sign_magnitude(raw, reg.sign_bit)
    return (raw & ((1 << (8 * reg.size)) - 1)).to_bytes(reg.size, "little")


def decode_value(reg: Register, data: bytes) -> int:
    raw = int.from_bytes(data[: reg.size], "little")
    if reg.sign_bit is not None:
        return from_sign_magnitude(raw, reg.sign_bit)
    return raw
