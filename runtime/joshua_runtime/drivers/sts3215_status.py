"""One telemetry reading per servo (position, speed, load, voltage, temperature, error bits) in one SYNC_READ."""

from dataclasses import asdict, dataclass

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import decode_value, register

TELEMETRY_FIRST = "Present_Position"
TELEMETRY_LAST = "Present_Current"
VOLTS_PER_UNIT = 0.1
MILLIAMPS_PER_UNIT = 6.5
LOAD_PERCENT_PER_UNIT = 0.1


@dataclass(frozen=True)
class ServoStatus:
    id: int
    position: int  # ticks
    speed: int  # ticks/s
    load_percent: float  # signed, of max torque
    voltage_v: float
    temperature_c: int
    error_bits: int
    moving: bool
    current_ma: float

    @property
    def errors(self) -> list[str]:
        return [name for bit, name in proto.ERROR_NAMES.items() if self.error_bits & bit]

    def as_json(self) -> dict:
        return {**asdict(self), "errors": self.errors}


def _span() -> tuple[int, int]:
    first, last = register(TELEMETRY_FIRST), register(TELEMETRY_LAST)
    return first.address, last.address + last.size - first.address


def decode_status(servo_id: int, block: bytes) -> ServoStatus:
    """A ServoStatus from the bytes of the telemetry span (Present_Position .. Present_Current)."""
    start, _ = _span()

    def value(name: str) -> int:
        reg = register(name)
        return decode_value(reg, block[reg.address - start : reg.address - start + reg.size])

    return ServoStatus(
        id=servo_id,
        position=value("Present_Position"),
        speed=value("Present_Velocity"),
        load_percent=round(value("Present_Load") * LOAD_PERCENT_PER_UNIT, 1),
        voltage_v=round(value("Present_Voltage") * VOLTS_PER_UNIT, 1),
        temperature_c=value("Present_Temperature"),
        error_bits=value("Status"),
        moving=bool(value("Moving")),
        current_ma=round(value("Present_Current") * MILLIAMPS_PER_UNIT, 1),
    )


def read_status(bus, ids: list[int]) -> list[ServoStatus]:
    """Telemetry of every servo in `ids`, in order, with one SYNC_READ."""
    address, size = _span()
    blocks = bus.sync_read_bytes(address, size, ids)
    return [decode_status(servo_id, blocks[servo_id]) for servo_id in ids]
