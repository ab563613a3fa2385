"""MOCK_ENCODER_PUBLISHER: JointState of `joint_names` moving as smooth sinusoids within SO-100 ranges.

Joint i swings around the middle of its range over 80 % of it, with period 4 s x (1 + i/4) and
phase i x 60 degrees (see mock_arm.swing); velocity is the exact derivative, effort is 0.
"""

import time

from sensor_msgs.msg import JointState

from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import mock_arm, settings_checks


class MockEncoderPublisher(JoshuaNode):
    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        period = settings_checks.period_s(self.settings)
        self.joint_names = list(self.settings.joint_names)
        if not self.joint_names:
            raise SettingsError("MOCK_ENCODER_PUBLISHER needs joint_names")
        self.frame_id = self.settings.frame_id
        self.started = time.monotonic()
        self.joint_states = self.publisher(topic)
        self.ros.create_timer(period, self._publish)

    def _publish(self) -> None:
        positions, velocities = mock_arm.swing(self.joint_names, time.monotonic() - self.started)
        message = JointState()
        message.header.stamp = self.stamp()
        message.header.frame_id = self.frame_id
        message.name = self.joint_names
        message.position = positions
        message.velocity = velocities
        message.effort = [0.0] * len(self.joint_names)
        self.joint_states.publish(message)
