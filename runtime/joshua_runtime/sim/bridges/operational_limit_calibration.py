"""OPERATIONAL_LIMIT_CALIBRATION in the simulation: the ranges a full sweep of the simulated arm would record.

Published as the real node publishes them (`<joint>.range_min` / `.range_max`, raw ticks with the
middle of each range at 2047) at `rate_hz`. No calibration file is written: the model knows its limits.
"""

from sensor_msgs.msg import JointState

from joshua_core.settings import NodeSettings
from joshua_runtime.drivers.calibration import HALF_TURN_TICKS, RADIANS_PER_TICK
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.operational_limit_calibration import RANGE_MAX_SUFFIX, RANGE_MIN_SUFFIX
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.engine import SimulationEngine


class CalibrationBridge(SimulationBridge):
    """Publishes the model's joint ranges like OPERATIONAL_LIMIT_CALIBRATION after a full sweep."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node, self.frame_id = node, settings.frame_id
        names = settings_checks.joints(settings)[1]
        engine.joints(names)  # every name must be a joint of the model
        self.names, self.limits = [], []
        for name in names:
            low, high = engine.model.joint(name).range
            self.names += [name + RANGE_MIN_SUFFIX, name + RANGE_MAX_SUFFIX]
            self.limits += [
                float(round(HALF_TURN_TICKS + low / RADIANS_PER_TICK)),
                float(round(HALF_TURN_TICKS + high / RADIANS_PER_TICK)),
            ]
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)
        if settings.calibration_file:
            node.log.info(f"{settings.name}: simulated, {settings.calibration_file} is left as it is")

    def publish(self) -> None:
        msg = JointState(name=self.names, position=self.limits)
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        self.publisher.publish(msg)
