"""sensor_msgs/PointCloud2 (float32 x y z intensity) from a PerceptionPacket's point_cloud or a LaserScan.

A lidar node publishes LaserScan or PointCloud2, whichever its topic's message_type names
(`scan_message`); the points are those of drivers/scan_geometry.py.
"""

from __future__ import annotations

import numpy as np
from sensor_msgs.msg import LaserScan, PointCloud2, PointField

from joshua_core.schema import PerceptionPacket
from joshua_runtime.convert.laser_scan import packet_to_laser_scan
from joshua_runtime.convert.stamp import to_ros_time
from joshua_runtime.drivers.scan_geometry import scan_points

POINT_CLOUD2 = "sensor_msgs/msg/PointCloud2"
_FIELDS = ("x", "y", "z", "intensity")
_POINT_STEP = 4 * len(_FIELDS)


def point_cloud2(xyz: np.ndarray, intensity: np.ndarray, header) -> PointCloud2:
    """An unorganized little-endian PointCloud2 with float32 fields x, y, z, intensity."""
    points = np.empty((len(xyz), len(_FIELDS)), dtype="<f4")
    points[:, :3] = xyz
    points[:, 3] = intensity
    message = PointCloud2(
        height=1,
        width=len(xyz),
        is_bigendian=False,
        point_step=_POINT_STEP,
        row_step=_POINT_STEP * len(xyz),
        is_dense=True,
    )
    message.fields = [
        PointField(name=name, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, name in enumerate(_FIELDS)
    ]
    message.data = points.tobytes()
    if header is not None:
        message.header = header
    return message


def packet_to_point_cloud2(packet: PerceptionPacket) -> PointCloud2:
    """The packet's point_cloud as a PointCloud2 stamped with the packet's timestamp and frame."""
    cloud = packet.point_cloud
    xyz = np.asarray(cloud.xyz, dtype=np.float32).reshape(-1, 3)
    intensity = np.asarray(cloud.intensity, dtype=np.float32)
    if len(intensity) != len(xyz):
        intensity = np.zeros(len(xyz), np.float32)
    message = point_cloud2(xyz, intensity, None)
    message.header.stamp = to_ros_time(packet.timestamp)
    message.header.frame_id = packet.frame_id
    return message


def laser_scan_to_point_cloud2(scan: LaserScan) -> PointCloud2:
    xyz, intensity = scan_points(
        scan.ranges, scan.intensities, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max
    )
    return point_cloud2(xyz, intensity, scan.header)


def scan_message(packet: PerceptionPacket, message_type: str):
    """The packet as the message a lidar topic of `message_type` carries (LaserScan or PointCloud2)."""
    return packet_to_point_cloud2(packet) if message_type == POINT_CLOUD2 else packet_to_laser_scan(packet)
