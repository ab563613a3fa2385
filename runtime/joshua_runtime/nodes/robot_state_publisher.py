"""ROBOT_STATE_PUBLISHER: the robot model on /robot_description and its link transforms on /tf and /tf_static.

Settings used: `topic` (sensor_msgs/msg/JointState to follow), `robot_description` (`builtin:so100`
or a URDF path). At start the URDF text goes out once on /robot_description and the fixed joints'
transforms once on /tf_static, both transient local so late subscribers get them. Every joint state
then becomes one tf2_msgs/TFMessage on /tf holding the parent-to-child transform of each movable joint
it names (forward kinematics of the URDF, urdf_model.py), stamped with the joint state's stamp. The
three topics, their types and QoS are its registry entry's fixed_topics, which the compiler's topology
reads too.

In MODE_SIMULATION this node runs beside the simulation engine and follows the joint states the
engine publishes for the simulated arm, so a simulated robot has the same /tf as a real one.
"""

from joshua_core.fixed_topics import ROBOT_DESCRIPTION, TF_STATIC, FixedTopic
from joshua_core.settings import QosSettings
from joshua_runtime.convert.transforms import TF_QOS, TF_TOPIC
from joshua_runtime.description.urdf_model import joint_transform, load, quaternion_xyzw
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.qos import qos_profile


def transform_message(joint, matrix, stamp):
    """A geometry_msgs/TransformStamped from a joint's parent link to its child link."""
    from geometry_msgs.msg import TransformStamped

    message = TransformStamped(child_frame_id=joint.child)
    message.header.frame_id = joint.parent
    message.header.stamp = stamp
    translation = message.transform.translation
    translation.x, translation.y, translation.z = (float(v) for v in matrix[:3, 3])
    rotation = message.transform.rotation
    rotation.x, rotation.y, rotation.z, rotation.w = quaternion_xyzw(matrix[:3, :3])
    return message


class RobotStatePublisher(JoshuaNode):
    def start(self) -> None:
        from std_msgs.msg import String
        from tf2_msgs.msg import TFMessage

        self.TFMessage = TFMessage
        self.model = load(self.settings.robot_description)
        self.movable = {joint.name: joint for joint in self.model.movable_joints}
        self.tf = self.ros.create_publisher(TFMessage, TF_TOPIC, TF_QOS)
        self.tf_static = self._fixed_publisher(TFMessage, TF_STATIC)
        self.description = self._fixed_publisher(String, ROBOT_DESCRIPTION)
        self.description.publish(String(data=self.model.text))
        now = self.stamp()
        self.tf_static.publish(
            TFMessage(transforms=[transform_message(joint, joint.origin, now) for joint in self.model.fixed_joints])
        )
        self.subscription(settings_checks.topic(self.settings), self._joint_state)
        self.log.info(
            f"publishing {self.model.name} ({len(self.movable)} joints) from {self.settings.topic.name} on {TF_TOPIC}"
        )

    def _fixed_publisher(self, message_class, topic: FixedTopic):
        """A publisher of one of the topics the registry says this node type publishes, with its QoS."""
        return self.ros.create_publisher(message_class, topic.name, qos_profile(QosSettings(**topic.qos)))

    def _joint_state(self, message) -> None:
        stamp = message.header.stamp if message.header.stamp.sec or message.header.stamp.nanosec else self.stamp()
        transforms = [
            transform_message(self.movable[name], joint_transform(self.movable[name], position), stamp)
            for name, position in zip(message.name, message.position)
            if name in self.movable
        ]
        if transforms:
            self.tf.publish(self.TFMessage(transforms=transforms))
