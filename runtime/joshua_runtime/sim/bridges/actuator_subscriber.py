"""ACTUATOR_SUBSCRIBER in the simulation: joint commands become position-actuator goals.

JointState commands from `topic` are matched by name (by order when the message has no names) and
clamped to the ranges; present states go to `state_topic` at `rate_hz` when one is set. Preset
commands on `<topic>/preset` move to poses as the real node does; `torque_off` (the e-stop) holds the
present pose and ignores goals until `torque_on`, as a simulated position actuator cannot go limp.
With a JointTrajectory topic, action chunks are followed as the real node follows them
(nodes/trajectory_follower.py), every 1/rate_hz.
"""

import math

import numpy as np
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_core.servo_topics import FIXED_QOS, TORQUE_OFF, TORQUE_ON, preset_topic
from joshua_core.settings import NodeSettings, QosSettings
from joshua_runtime import presets
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.trajectory_follower import ChunkCommands, is_trajectory
from joshua_runtime.qos import qos_profile
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.joint_state_source import JointStateSource


class ActuatorBridge(SimulationBridge):
    """Applies JointState commands to position actuators like ACTUATOR_SUBSCRIBER."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.engine = engine
        self.group = engine.joints(settings_checks.joints(settings)[1], actuated=True)
        self._index = {name: i for i, name in enumerate(self.group.names)}
        topic = settings_checks.topic(settings)
        if is_trajectory(topic):
            period = settings_checks.period_s(settings)
            self.chunks = ChunkCommands(node, topic, list(self.group.names), period, self.on_goals)
        else:
            self.subscription = node.subscription(topic, self.on_command)
        self.poses = presets.poses({p.name: dict(p.positions) for p in settings.preset})
        self.frozen = False  # after torque_off, until torque_on
        self.presets = node.ros.create_subscription(
            String, preset_topic(topic.name), self.on_preset, qos_profile(QosSettings(**FIXED_QOS))
        )
        self.state_publisher = None
        if settings.HasField("state_topic"):
            self.source = JointStateSource(node, engine, self.group, settings.frame_id)
            self.state_publisher = node.publisher(settings.state_topic)
            self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish_state)

    def goals(self, msg: JointState) -> np.ndarray:
        """Goal per joint of the group: matched by name, else by order when the lengths agree; NaN = keep."""
        goals = np.full(len(self.group.names), math.nan)
        positions = list(msg.position)
        if msg.name:
            for name, value in zip(msg.name, positions):
                i = self._index.get(name)
                if i is not None:
                    goals[i] = value
        elif len(positions) == len(goals):
            goals[:] = positions
        return goals

    def on_command(self, msg: JointState) -> None:
        self.on_goals(self.goals(msg))

    def on_goals(self, goals: np.ndarray) -> None:
        if not self.frozen:
            self.engine.command(self.group, goals)

    def on_preset(self, msg: String) -> None:
        action = presets.expand(msg.data.strip(), self.poses, list(self.group.names))
        if action is None:
            return
        if TORQUE_OFF in action.preset_commands:
            self.frozen = True
            self.engine.command(self.group, self.engine.read(self.group).positions)
        elif TORQUE_ON in action.preset_commands:
            self.frozen = False
        elif not self.frozen:
            self.engine.command(self.group, np.array(action.position, dtype=float))

    def publish_state(self) -> None:
        self.state_publisher.publish(self.source.message())
