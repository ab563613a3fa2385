"""DIFF_DRIVE_BASE in the simulation: Twist drives the model's wheel velocity actuators, odometry comes
from the simulated wheel angles through the same code as on the real base (nodes/diff_drive.py)."""

from joshua_core.settings import NodeSettings
from joshua_runtime.nodes.diff_drive import BaseTopics, WheelDrive, wheel_names
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.engine import SimulationEngine


class SimulatedWheels(WheelDrive):
    """The model's two wheel joints, driven by velocity actuators (control: rad/s)."""

    def __init__(self, engine: SimulationEngine, names: list[str]):
        self.engine = engine
        self.group = engine.joints(names, actuated=True)

    def set_wheel_speeds(self, left_rad_s: float, right_rad_s: float) -> None:
        self.engine.command(self.group, [left_rad_s, right_rad_s])

    def wheel_angles(self):
        reading = self.engine.read(self.group)
        return float(reading.positions[0]), float(reading.positions[1]), reading.sim_time


class DiffDriveBridge(SimulationBridge):
    """Serves the base's topics, types and QoS for the simulated car."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.topics = BaseTopics(node, settings, SimulatedWheels(engine, wheel_names(settings)))
