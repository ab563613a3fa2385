"""ENCODER_PUBLISHER: publishes the joint states of an STS3215 bus (e.g. a leader arm) as JointState.

The arm is moved by hand, so torque is switched off when the bus opens (and again after a
reconnect). Every 1/rate_hz one SYNC_READ gives position (rad), velocity (rad/s) and effort
(signed fraction of max torque) for `joint_names`, calibrated by `calibration_file` when set. Servo health goes to /diagnostics
(servo_diagnostics).
"""

from joshua_runtime.convert.joint_state import perception_to_joint_state
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.servo_bus import BusGuard, bus_from_settings
from joshua_runtime.nodes.servo_diagnostics import ServoDiagnostics


class EncoderPublisher(JoshuaNode):
    bus = None

    def start(self) -> None:
        period = settings_checks.period_s(self.settings)
        self.bus = bus_from_settings(self.settings)
        self.bus.open()
        self.bus.disable_torque()
        self.guard = BusGuard(self.bus, self.log, on_reconnect=self.bus.disable_torque)
        self.frame_id = self.settings.frame_id
        self.joint_states = self.publisher(settings_checks.topic(self.settings))
        self.ros.create_timer(period, self._publish)
        self.diagnostics = ServoDiagnostics(self, self.guard)

    def _publish(self) -> None:
        packet = self.guard.call(self.bus.read_state)
        if packet is not None:
            self.joint_states.publish(perception_to_joint_state(packet, frame_id=self.frame_id))

    def close(self) -> None:
        if self.bus is not None:
            self.bus.close()
