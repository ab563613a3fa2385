"""/diagnostics for the nodes the simulation stands in for: one OK status per simulated servo and base.

The real nodes report each servo's temperature, voltage and load (nodes/servo_diagnostics.py) and a
base's hub link (nodes/hub_link.py); a simulated robot has none of these, so each status says it is
simulated, a servo's with the joint's position. Published at the fastest diagnostics_rate_hz of the
simulated nodes, on the same topic, type and QoS as the real nodes.
"""

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from joshua_core.node_types import spec
from joshua_core.servo_topics import DIAGNOSTICS_RATE_HZ, DIAGNOSTICS_TOPIC, FIXED_QOS
from joshua_core.settings import NodeSettings, QosSettings
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.hub_link import STATUS_SUFFIX as HUB_STATUS_SUFFIX
from joshua_runtime.qos import qos_profile
from joshua_runtime.sim.engine import SimulationEngine

HARDWARE_ID = "simulation"


class SimulatedDiagnostics:
    def __init__(self, node, engine: SimulationEngine, simulated: list[NodeSettings]):
        self.node, self.engine = node, engine
        reporting = [s for s in simulated if spec(s.type).diagnostics]
        servo_nodes = [s for s in reporting if spec(s.type).servo_bus]
        self.joints = [(s.name, engine.joints(settings_checks.joints(s)[1])) for s in servo_nodes]
        self.bases = [s.name for s in reporting if not spec(s.type).servo_bus]
        self.publisher = None
        if reporting:
            rate = max(s.diagnostics_rate_hz or DIAGNOSTICS_RATE_HZ for s in reporting)
            self.publisher = node.ros.create_publisher(
                DiagnosticArray, DIAGNOSTICS_TOPIC, qos_profile(QosSettings(**FIXED_QOS))
            )
            self.timer = node.ros.create_timer(1.0 / rate, self.publish)

    def publish(self) -> None:
        message = DiagnosticArray()
        message.header.stamp = self.node.stamp()
        for name, group in self.joints:
            positions = self.engine.read(group).positions
            for joint, position in zip(group.names, positions):
                message.status.append(
                    DiagnosticStatus(
                        level=DiagnosticStatus.OK,
                        name=f"{name}: {joint}",
                        hardware_id=HARDWARE_ID,
                        message="simulated",
                        values=[KeyValue(key="position_rad", value=f"{position:.4f}")],
                    )
                )
        for name in self.bases:
            message.status.append(
                DiagnosticStatus(
                    level=DiagnosticStatus.OK,
                    name=name + HUB_STATUS_SUFFIX,
                    hardware_id=HARDWARE_ID,
                    message="simulated",
                )
            )
        self.publisher.publish(message)
