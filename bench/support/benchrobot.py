"""A LeRobot `Robot` for the bench: tiny_act's camera picture and arm pose of the moment; actions go nowhere.

LeRobot finds a robot class by its config's module and name (`<parent>.<name in lower case>`), hence this
module's name.
"""

import time
from dataclasses import dataclass

from lerobot.robots.config import RobotConfig
from lerobot.robots.robot import Robot

from testsupport import tiny_act


@RobotConfig.register_subclass("joshua_bench")
@dataclass
class BenchRobotConfig(RobotConfig):
    """No settings: the robot is synthetic."""


class BenchRobot(Robot):
    """Observes tiny_act's camera picture and arm pose of the moment; records when each action arrives."""

    config_class = BenchRobotConfig
    name = "joshua_bench"

    def __init__(self, config: BenchRobotConfig):
        super().__init__(config)
        self.started = time.monotonic()
        self.connected = False

    @property
    def observation_features(self) -> dict:
        return {**{f"{joint}.pos": float for joint in tiny_act.JOINTS}, "camera": (tiny_act.HEIGHT, tiny_act.WIDTH, 3)}

    @property
    def action_features(self) -> dict:
        return {f"{joint}.pos": float for joint in tiny_act.JOINTS}

    @property
    def is_connected(self) -> bool:
        return self.connected

    def connect(self, calibrate: bool = True) -> None:
        self.connected = True

    @property
    def is_calibrated(self) -> bool:
        return True

    def calibrate(self) -> None:
        pass

    def configure(self) -> None:
        pass

    def get_observation(self) -> dict:
        t = time.monotonic() - self.started
        observation = {f"{joint}.pos": float(value) for joint, value in zip(tiny_act.JOINTS, tiny_act.pose(t))}
        observation["camera"] = tiny_act.frame_image(t)
        return observation

    def send_action(self, action: dict) -> dict:
        return action

    def disconnect(self) -> None:
        self.connected = False
