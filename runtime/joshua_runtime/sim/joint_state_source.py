"""JointState messages of a group of simulated joints, in the units of the real drivers.

Radians, rad/s, and effort as a signed fraction of the actuator's force limit (as the STS3215 driver
reports it); header stamps are the ROS clock, frame_id the node's. Used by the encoder and actuator
bridges, so a simulated arm reports its joints as the real nodes do.
"""

import array

import numpy as np
from sensor_msgs.msg import JointState

from joshua_runtime.sim.engine import JointGroup, SimulationEngine


class JointStateSource:
    """Turns a JointGroup reading into JointState messages (real-driver units)."""

    def __init__(self, node, engine: SimulationEngine, group: JointGroup, frame_id: str):
        self.node, self.engine, self.group, self.frame_id = node, engine, group, frame_id
        limits = np.array(
            [
                abs(engine.model.actuator_forcerange[a, 1]) if a >= 0 and engine.model.actuator_forcelimited[a] else 0.0
                for a in group.actuators
            ]
        )
        self._effort_scale = np.where(limits > 0, 1.0 / np.where(limits > 0, limits, 1.0), 1.0)

    def message(self) -> JointState:
        reading = self.engine.read(self.group)
        msg = JointState()
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        msg.name = list(self.group.names)
        msg.position = array.array("d", reading.positions.tobytes())
        msg.velocity = array.array("d", reading.velocities.tobytes())
        msg.effort = array.array("d", (reading.efforts * self._effort_scale).tobytes())
        return msg
