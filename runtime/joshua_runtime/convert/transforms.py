"""The /tf topic every node that broadcasts transforms shares, and Odometry -> TransformStamped."""

from geometry_msgs.msg import TransformStamped

from joshua_core.fixed_topics import TF
from joshua_core.settings import QosSettings
from joshua_runtime.qos import qos_profile

TF_TOPIC = TF.name
TF_QOS = qos_profile(QosSettings(**TF.qos))


def odometry_transform(odometry) -> TransformStamped:
    """The transform an Odometry message states: its frame_id (odom) to its child_frame_id (base_link)."""
    transform = TransformStamped(header=odometry.header, child_frame_id=odometry.child_frame_id)
    position, orientation = odometry.pose.pose.position, odometry.pose.pose.orientation
    transform.transform.translation.x, transform.transform.translation.y = position.x, position.y
    transform.transform.translation.z = position.z
    transform.transform.rotation = orientation
    return transform
