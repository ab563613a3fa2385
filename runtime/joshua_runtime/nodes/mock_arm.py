"""A simulated SO-100 arm for the MOCK_* nodes: joint ranges, smooth motion and first-order tracking."""

import math

from joshua_core.so100 import SO100_RANGES

OTHER_JOINT_RANGE = (-1.0, 1.0)  # a joint name the SO-100 does not have
# Sinusoid of joint i: amplitude SWING_FRACTION of the half range, period BASE_PERIOD_S * (1 + i / 4).
SWING_FRACTION = 0.8
BASE_PERIOD_S = 4.0
PERIOD_STEP = 0.25
# Time constant of the simulated arm following its commands.
TRACKING_TIME_CONSTANT_S = 0.1


def joint_range(name: str) -> tuple[float, float]:
    return SO100_RANGES.get(name, OTHER_JOINT_RANGE)


def clamp(name: str, value: float) -> float:
    low, high = joint_range(name)
    return min(max(value, low), high)


def home_position(name: str) -> float:
    """Where a simulated joint starts: 0 rad, which is inside every range."""
    return clamp(name, 0.0)


def swing(names: list[str], t: float) -> tuple[list[float], list[float]]:
    """Positions and velocities of smooth, out-of-phase sinusoids within each joint's range at time t."""
    positions, velocities = [], []
    for i, name in enumerate(names):
        low, high = joint_range(name)
        centre, amplitude = (low + high) / 2, SWING_FRACTION * (high - low) / 2
        omega = 2 * math.pi / (BASE_PERIOD_S * (1 + PERIOD_STEP * i))
        phase = i * math.pi / 3
        positions.append(centre + amplitude * math.sin(omega * t + phase))
        velocities.append(amplitude * omega * math.cos(omega * t + phase))
    return positions, velocities


def track(position: float, target: float, dt: float, time_constant: float = TRACKING_TIME_CONSTANT_S) -> float:
    """One step of first-order motion toward `target` over `dt` seconds."""
    return target + (position - target) * math.exp(-dt / time_constant)
