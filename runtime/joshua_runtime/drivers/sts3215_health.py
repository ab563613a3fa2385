"""Judge a servo status reading against the STS3215 limits: one (level, message) per concern.

Levels follow diagnostic_msgs/DiagnosticStatus (OK 0, WARN 1, ERROR 2) so a ROS node can publish
them unchanged. Limits are the servo's factory protection settings (control table defaults); a
reading within WARN_MARGIN of a limit warns before the servo protects itself.
"""

from dataclasses import dataclass

from joshua_runtime.drivers.sts3215_status import (
    LOAD_PERCENT_PER_UNIT,
    VOLTS_PER_UNIT,
    ServoStatus,
)
from joshua_runtime.drivers.sts3215_table import BY_NAME

OK, WARN, ERROR = 0, 1, 2
TEMPERATURE_WARN_MARGIN_C = 10
VOLTAGE_WARN_MARGIN_V = 0.5


@dataclass(frozen=True)
class Limits:
    max_temperature_c: float = BY_NAME["Max_Temperature_Limit"].default
    min_voltage_v: float = BY_NAME["Min_Voltage_Limit"].default * VOLTS_PER_UNIT
    max_voltage_v: float = BY_NAME["Max_Voltage_Limit"].default * VOLTS_PER_UNIT
    overload_percent: float = BY_NAME["Overload_Torque"].default
    max_load_percent: float = BY_NAME["Max_Torque_Limit"].default * LOAD_PERCENT_PER_UNIT


STS3215_LIMITS = Limits()


@dataclass(frozen=True)
class Finding:
    level: int
    message: str


def assess(status: ServoStatus, limits: Limits = STS3215_LIMITS) -> list[Finding]:
    """Every concern about one reading, worst first; an empty list means OK."""
    findings = [Finding(ERROR, f"servo reports {name}") for name in status.errors]
    temperature = status.temperature_c
    if temperature >= limits.max_temperature_c:
        findings.append(Finding(ERROR, f"temperature {temperature} C at or above {limits.max_temperature_c:g} C"))
    elif temperature >= limits.max_temperature_c - TEMPERATURE_WARN_MARGIN_C:
        findings.append(Finding(WARN, f"temperature {temperature} C near {limits.max_temperature_c:g} C"))
    volts = status.voltage_v
    if not limits.min_voltage_v <= volts <= limits.max_voltage_v:
        findings.append(
            Finding(ERROR, f"voltage {volts:.1f} V outside {limits.min_voltage_v:.1f}-{limits.max_voltage_v:.1f} V")
        )
    elif min(volts - limits.min_voltage_v, limits.max_voltage_v - volts) < VOLTAGE_WARN_MARGIN_V:
        findings.append(Finding(WARN, f"voltage {volts:.1f} V near its limit"))
    load = abs(status.load_percent)
    if load >= limits.max_load_percent:
        findings.append(Finding(ERROR, f"load {load:.0f} % at maximum torque"))
    elif load >= limits.overload_percent:
        findings.append(Finding(WARN, f"load {load:.0f} % above {limits.overload_percent:g} %"))
    return sorted(findings, key=lambda finding: -finding.level)


def level(findings: list[Finding]) -> int:
    """The overall level of a servo: its worst finding, OK when there is none."""
    return max((finding.level for finding in findings), default=OK)


def read_failure(servo_id: int, reason: str) -> Finding:
    """The finding for a servo that could not be read at all."""
    return Finding(ERROR, f"servo id {servo_id} unreadable: {reason}")
