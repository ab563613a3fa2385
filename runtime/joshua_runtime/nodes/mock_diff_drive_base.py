"""MOCK_DIFF_DRIVE_BASE: ideal wheels that turn exactly at the commanded speeds, on the topics of DIFF_DRIVE_BASE."""

import time

from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes.diff_drive import BaseTopics, WheelDrive


class IdealWheels(WheelDrive):
    def __init__(self):
        self.speeds = (0.0, 0.0)
        self.angles = (0.0, 0.0)
        self.since = time.monotonic()

    def _advance(self) -> float:
        now = time.monotonic()
        dt, self.since = now - self.since, now
        self.angles = (self.angles[0] + self.speeds[0] * dt, self.angles[1] + self.speeds[1] * dt)
        return now

    def set_wheel_speeds(self, left_rad_s: float, right_rad_s: float) -> None:
        self._advance()
        self.speeds = (left_rad_s, right_rad_s)

    def wheel_angles(self):
        now = self._advance()
        return self.angles[0], self.angles[1], now


class MockDiffDriveBase(JoshuaNode):
    def start(self) -> None:
        self.topics = BaseTopics(self, self.settings, IdealWheels())
