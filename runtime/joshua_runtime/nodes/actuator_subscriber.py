"""ACTUATOR_SUBSCRIBER: drives an STS3215 bus (e.g. a follower arm) from JointState commands.

On start the servos hold their present pose and torque goes on. Each command on `topic` is matched to
`joint_names` by name (absent joints keep their goal), converted to raw goals clamped to the
calibrated range, and sent at once in one SYNC_WRITE. Only positions are used: a leader's present
velocity is no speed limit. With `state_topic` set, the bus's present joint states are published
there every 1/rate_hz. Torque goes off when the node stops, unless keep_torque_on_exit is set.
"""

from joshua_runtime.convert.joint_state import joint_state_to_action, perception_to_joint_state
from joshua_runtime.errors import DeviceError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.servo_bus import BusGuard, bus_from_settings


class ActuatorSubscriber(JoshuaNode):
    bus = None

    def start(self) -> None:
        period = settings_checks.period_s(self.settings)
        self.bus = bus_from_settings(self.settings)
        self.bus.open()
        self.bus.enable_torque()
        self.guard = BusGuard(self.bus, self.log, on_reconnect=self.bus.enable_torque)
        self.frame_id = self.settings.frame_id
        self.subscription(settings_checks.topic(self.settings), self._command)
        if self.settings.HasField("state_topic"):
            self.joint_states = self.publisher(self.settings.state_topic)
            self.ros.create_timer(period, self._publish_state)

    def _command(self, message) -> None:
        action = joint_state_to_action(message, self.bus.joint_names)
        if len(action.position) == len(self.bus.ids):
            self.guard.call(self.bus.write_action, action)

    def _publish_state(self) -> None:
        packet = self.guard.call(self.bus.read_state)
        if packet is not None:
            self.joint_states.publish(perception_to_joint_state(packet, frame_id=self.frame_id))

    def close(self) -> None:
        if self.bus is None:
            return
        try:
            if self.bus.is_open and not self.settings.keep_torque_on_exit:
                self.bus.disable_torque()
        except DeviceError as exc:
            self.log.warning(f"torque left on: {exc}")
        finally:
            self.bus.close()
