"""Servo readings judged against the STS3215 limits, as the diagnostics publisher will report them."""

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_health import (
    ERROR,
    OK,
    WARN,
    Finding,
    assess,
    level,
    read_failure,
)
from joshua_runtime.drivers.sts3215_status import ServoStatus, read_status
from joshua_runtime.servo_tools.bus import open_bus


def reading(**changes) -> ServoStatus:
    values = {
        "id": 1,
        "position": 2048,
        "speed": 0,
        "load_percent": 0.0,
        "voltage_v": 12.1,
        "temperature_c": 30,
        "error_bits": 0,
        "moving": False,
        "current_ma": 0.0,
    }
    return ServoStatus(**{**values, **changes})


def test_healthy_servo_is_ok():
    assert assess(reading()) == [] and level([]) == OK


def test_levels_follow_the_factory_limits():
    assert assess(reading(temperature_c=62)) == [Finding(WARN, "temperature 62 C near 70 C")]
    assert assess(reading(temperature_c=70)) == [Finding(ERROR, "temperature 70 C at or above 70 C")]
    assert assess(reading(voltage_v=4.2)) == [Finding(WARN, "voltage 4.2 V near its limit")]
    assert assess(reading(voltage_v=3.5)) == [Finding(ERROR, "voltage 3.5 V outside 4.0-14.0 V")]
    assert assess(reading(load_percent=-85.0)) == [Finding(WARN, "load 85 % above 80 %")]
    assert assess(reading(load_percent=100.0)) == [Finding(ERROR, "load 100 % at maximum torque")]
    assert read_failure(4, "no answer").level == ERROR


def test_error_bits_come_first_and_set_the_level():
    findings = assess(reading(error_bits=proto.ERROR_OVERLOAD | proto.ERROR_ANGLE_SENSOR, temperature_c=61))
    assert [f.message for f in findings] == [
        "servo reports angle sensor",
        "servo reports overload",
        "temperature 61 C near 70 C",
    ]
    assert level(findings) == ERROR


def test_emulated_overheat_reads_as_an_error(emulators):
    emulator = emulators("ttyDIAG", ids=[1, 2])
    emulator.set_sensor(2, "Present_Temperature", 72)
    with open_bus(str(emulator.link)) as bus:
        first, second = read_status(bus, [1, 2])
    assert level(assess(first)) == OK
    assert [f.message for f in assess(second)] == ["servo reports overheat", "temperature 72 C at or above 70 C"]
