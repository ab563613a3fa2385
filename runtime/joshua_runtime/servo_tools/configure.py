"""Change a servo's id or baud rate and make it stick: unlock the EEPROM, write, lock, check."""

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import BAUD_RATE_CODES
from joshua_runtime.drivers.sts3215_transport import NoAnswer
from joshua_runtime.errors import JoshuaError
from joshua_runtime.servo_tools.scan import FoundServo, find, identify


class UsageError(JoshuaError):
    """The command asks for something the servo cannot do."""


def _write_eeprom(bus, servo_id: int, name: str, value: int) -> None:
    bus.write(servo_id, "Torque_Enable", 0)
    bus.write(servo_id, "Lock", 0)
    bus.write(servo_id, name, value)


def set_id(bus, old_id: int, new_id: int) -> FoundServo:
    """Give servo `old_id` the id `new_id` at its own baud rate; refuses an id already taken."""
    if not 0 <= new_id <= proto.MAX_SERVO_ID:
        raise UsageError(f"servo ids are 0-{proto.MAX_SERVO_ID}, not {new_id}")
    servo = find(bus, old_id)
    if new_id == old_id:
        return servo
    try:
        taken = identify(bus, new_id, servo.baud_rate)
    except NoAnswer:
        taken = None
    if taken is not None:
        raise UsageError(f"{bus.port}: id {new_id} is already taken at {servo.baud_rate} baud")
    _write_eeprom(bus, old_id, "ID", new_id)
    bus.write(new_id, "Lock", 1)
    return identify(bus, new_id, servo.baud_rate)


def set_baud(bus, servo_id: int, baud_rate: int) -> FoundServo:
    """Switch servo `servo_id` to `baud_rate`, then talk to it there to lock and check it."""
    if baud_rate not in BAUD_RATE_CODES:
        rates = ", ".join(map(str, BAUD_RATE_CODES))
        raise UsageError(f"STS3215 baud rates are {rates}, not {baud_rate}")
    servo = find(bus, servo_id)
    if servo.baud_rate == baud_rate:
        return servo
    _write_eeprom(bus, servo_id, "Baud_Rate", BAUD_RATE_CODES[baud_rate])
    bus.transport.set_baud_rate(baud_rate)
    bus.write(servo_id, "Lock", 1)
    return identify(bus, servo_id, baud_rate)
