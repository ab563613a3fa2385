"""Every message type of std_msgs, sensor_msgs, geometry_msgs, nav_msgs, diagnostic_msgs, trajectory_msgs and
tf2_msgs in ROS 2 Jazzy.

Taken from the `.msg` files of the Jazzy packages (std_msgs, sensor_msgs, geometry_msgs, nav_msgs,
diagnostic_msgs and trajectory_msgs 5.3.6; tf2_msgs 0.36 defines TF2Error and TFMessage, built by set-up from
interfaces/). Names use the ROS 2 form `pkg/msg/Type`.
"""

from __future__ import annotations

import difflib
import re

PACKAGES: dict[str, tuple[str, ...]] = {
    "std_msgs": (
        "Bool",
        "Byte",
        "ByteMultiArray",
        "Char",
        "ColorRGBA",
        "Empty",
        "Float32",
        "Float32MultiArray",
        "Float64",
        "Float64MultiArray",
        "Header",
        "Int16",
        "Int16MultiArray",
        "Int32",
        "Int32MultiArray",
        "Int64",
        "Int64MultiArray",
        "Int8",
        "Int8MultiArray",
        "MultiArrayDimension",
        "MultiArrayLayout",
        "String",
        "UInt16",
        "UInt16MultiArray",
        "UInt32",
        "UInt32MultiArray",
        "UInt64",
        "UInt64MultiArray",
        "UInt8",
        "UInt8MultiArray",
    ),
    "sensor_msgs": (
        "BatteryState",
        "CameraInfo",
        "ChannelFloat32",
        "CompressedImage",
        "FluidPressure",
        "Illuminance",
        "Image",
        "Imu",
        "JointState",
        "Joy",
        "JoyFeedback",
        "JoyFeedbackArray",
        "LaserEcho",
        "LaserScan",
        "MagneticField",
        "MultiDOFJointState",
        "MultiEchoLaserScan",
        "NavSatFix",
        "NavSatStatus",
        "PointCloud",
        "PointCloud2",
        "PointField",
        "Range",
        "RegionOfInterest",
        "RelativeHumidity",
        "Temperature",
        "TimeReference",
    ),
    "geometry_msgs": (
        "Accel",
        "AccelStamped",
        "AccelWithCovariance",
        "AccelWithCovarianceStamped",
        "Inertia",
        "InertiaStamped",
        "Point",
        "Point32",
        "PointStamped",
        "Polygon",
        "PolygonInstance",
        "PolygonInstanceStamped",
        "PolygonStamped",
        "Pose",
        "Pose2D",
        "PoseArray",
        "PoseStamped",
        "PoseWithCovariance",
        "PoseWithCovarianceStamped",
        "Quaternion",
        "QuaternionStamped",
        "Transform",
        "TransformStamped",
        "Twist",
        "TwistStamped",
        "TwistWithCovariance",
        "TwistWithCovarianceStamped",
        "Vector3",
        "Vector3Stamped",
        "VelocityStamped",
        "Wrench",
        "WrenchStamped",
    ),
    "nav_msgs": (
        "Goals",
        "GridCells",
        "MapMetaData",
        "OccupancyGrid",
        "Odometry",
        "Path",
    ),
    "diagnostic_msgs": (
        "DiagnosticArray",
        "DiagnosticStatus",
        "KeyValue",
    ),
    "trajectory_msgs": (
        "JointTrajectory",
        "JointTrajectoryPoint",
        "MultiDOFJointTrajectory",
        "MultiDOFJointTrajectoryPoint",
    ),
    "tf2_msgs": (
        "TF2Error",
        "TFMessage",
    ),
}
MESSAGE_TYPES: frozenset[str] = frozenset(f"{pkg}/msg/{name}" for pkg, names in PACKAGES.items() for name in names)
_FORM = re.compile(r"^[a-z][a-z0-9_]*/msg/[A-Z][A-Za-z0-9]*$")
SUGGESTION_CUTOFF = 0.75


def is_known(message_type: str) -> bool:
    return message_type in MESSAGE_TYPES


def is_well_formed(message_type: str) -> bool:
    """Whether the text has the `pkg/msg/Type` form (whatever the package)."""
    return bool(_FORM.match(message_type))


def closest(message_type: str) -> str | None:
    """The catalogue entry the text most likely meant: `sensor_msgs/Image` -> `sensor_msgs/msg/Image`."""
    parts = message_type.replace("::", "/").replace(".", "/").split("/")
    if len(parts) == 2 and f"{parts[0]}/msg/{parts[1]}" in MESSAGE_TYPES:
        return f"{parts[0]}/msg/{parts[1]}"
    lowered = {t.lower(): t for t in MESSAGE_TYPES}
    if message_type.lower() in lowered:
        return lowered[message_type.lower()]
    matches = difflib.get_close_matches(message_type, sorted(MESSAGE_TYPES), n=1, cutoff=SUGGESTION_CUTOFF)
    return matches[0] if matches else None
