"""What the desktop panel shows and sends, independent of Qt and of the link (serial bus or ROS)."""

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

from joshua_core.servo_topics import TORQUE_OFF, TORQUE_ON
from joshua_core.so100 import SO100_JOINTS, SO100_RANGES
from joshua_runtime.errors import SettingsError
from joshua_runtime.presets import BUILTIN_PRESETS

PRESET_TORQUE_ON = TORQUE_ON
PRESET_TORQUE_OFF = TORQUE_OFF
NAN = math.nan


@dataclass(frozen=True)
class JointSample:
    """One reading of one joint; None where the link cannot tell (ROS carries no temperature)."""

    position: float  # rad
    load_percent: float
    temperature_c: float | None = None
    voltage_v: float | None = None
    torque_on: bool | None = None
    errors: tuple[str, ...] = ()
    health: int | None = None  # diagnostic level (0 OK, 1 WARN, 2 ERROR) where the link can judge it
    findings: tuple[str, ...] = ()


@dataclass(frozen=True)
class Telemetry:
    """One reading of every joint, stamped with the monotonic time it arrived."""

    time_s: float
    joints: dict[str, JointSample]


@dataclass(frozen=True)
class JointLimits:
    low: float
    high: float


def so100_limits() -> dict[str, JointLimits]:
    return {name: JointLimits(*SO100_RANGES[name]) for name in SO100_JOINTS}


@dataclass
class Presets:
    """Named poses: the built-in ones plus a user's, loaded from a JSON file of {name: {joint: rad}}."""

    poses: dict[str, dict[str, float]] = field(default_factory=lambda: dict(BUILTIN_PRESETS))

    def names(self) -> list[str]:
        return list(self.poses)

    def goals(self, name: str, joints: list[str]) -> list[float]:
        """The pose in joint order, NaN for joints the preset leaves alone."""
        pose = self.poses[name]
        return [pose.get(joint, NAN) for joint in joints]


def load_presets(path: str | os.PathLike | None, joints: list[str]) -> Presets:
    """Built-in presets plus those of `path`; SettingsError names the file and the bad entry."""
    presets = Presets()
    if not path:
        return presets
    path = Path(path)
    try:
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise SettingsError(f"preset file {path} not found") from None
    except (OSError, ValueError) as exc:
        raise SettingsError(f"preset file {path} is unreadable: {exc}") from None
    if not isinstance(document, dict):
        raise SettingsError(f"preset file {path}: expected an object of preset names")
    for name, pose in document.items():
        if not isinstance(pose, dict) or not pose:
            raise SettingsError(f"preset file {path}: preset {name!r} must map joint names to radians")
        for joint, value in pose.items():
            if joint not in joints:
                raise SettingsError(f"preset file {path}: preset {name!r} names unknown joint {joint!r}")
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise SettingsError(f"preset file {path}: preset {name!r}: {joint} must be a number of radians")
        presets.poses[name] = {joint: float(value) for joint, value in pose.items()}
    return presets
