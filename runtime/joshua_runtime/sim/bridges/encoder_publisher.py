"""ENCODER_PUBLISHER in the simulation: JointState of `joint_names` on `topic` at `rate_hz`."""

from joshua_core.settings import NodeSettings
from joshua_runtime.nodes import settings_checks
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.joint_state_source import JointStateSource


class EncoderBridge(SimulationBridge):
    """Publishes present joint states like ENCODER_PUBLISHER."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        group = engine.joints(settings_checks.joints(settings)[1])
        self.source = JointStateSource(node, engine, group, settings.frame_id)
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)

    def publish(self) -> None:
        self.publisher.publish(self.source.message())
