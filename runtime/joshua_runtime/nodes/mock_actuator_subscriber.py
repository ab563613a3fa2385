"""MOCK_ACTUATOR_SUBSCRIBER: a simulated arm that follows JointState commands or action chunks on `topic`.

Each joint of `joint_names` starts at 0 rad and moves first-order toward its last command
(time constant mock_arm.TRACKING_TIME_CONSTANT_S), clamped to its SO-100 range. Commands are
matched by joint name; a command without names is taken in joint order when its length matches;
unknown names and NaN positions are ignored. With a trajectory_msgs/msg/JointTrajectory topic, the
command of each step (every 1/rate_hz) is the chunk's goal at that moment (nodes/trajectory_follower.py).
Every 1/rate_hz the present positions and velocities are published on `state_topic` when it is set.
"""

import math
import time

from sensor_msgs.msg import JointState

from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import mock_arm, settings_checks
from joshua_runtime.nodes.trajectory_follower import ChunkCommands, is_trajectory


class MockActuatorSubscriber(JoshuaNode):
    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        period = settings_checks.period_s(self.settings)
        self.joint_names = list(self.settings.joint_names)
        if not self.joint_names:
            raise SettingsError("MOCK_ACTUATOR_SUBSCRIBER needs joint_names")
        self.frame_id = self.settings.frame_id
        self.positions = {name: mock_arm.home_position(name) for name in self.joint_names}
        self.velocities = dict.fromkeys(self.joint_names, 0.0)
        self.targets = dict(self.positions)
        self.commands_received = 0
        self.last_step = time.monotonic()
        if is_trajectory(topic):
            self.chunks = ChunkCommands(self, topic, self.joint_names, period, self._aim)
        else:
            self.subscription(topic, self._command)
        self.states = self.publisher(self.settings.state_topic) if self.settings.HasField("state_topic") else None
        self.ros.create_timer(period, self._step)

    def _command(self, message: JointState) -> None:
        names = list(message.name) or (self.joint_names if len(message.position) == len(self.joint_names) else [])
        for name, position in zip(names, message.position):
            if name in self.targets and not math.isnan(position):
                self.targets[name] = mock_arm.clamp(name, position)
        self.commands_received += 1

    def _aim(self, goals) -> None:
        """Targets from an action chunk's goals in joint order (NaN: keep)."""
        for name, position in zip(self.joint_names, goals):
            if not math.isnan(position):
                self.targets[name] = mock_arm.clamp(name, float(position))

    def _step(self) -> None:
        now = time.monotonic()
        dt, self.last_step = now - self.last_step, now
        for name in self.joint_names:
            previous = self.positions[name]
            self.positions[name] = mock_arm.track(previous, self.targets[name], dt)
            self.velocities[name] = (self.positions[name] - previous) / dt if dt > 0 else 0.0
        if self.states is not None:
            message = JointState()
            message.header.stamp = self.stamp()
            message.header.frame_id = self.frame_id
            message.name = self.joint_names
            message.position = [self.positions[name] for name in self.joint_names]
            message.velocity = [self.velocities[name] for name in self.joint_names]
            message.effort = [0.0] * len(self.joint_names)
            self.states.publish(message)
