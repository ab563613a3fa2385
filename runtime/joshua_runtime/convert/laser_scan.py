"""sensor_msgs/LaserScan <-> PerceptionPacket with a "laser_scan" SensorData."""

from sensor_msgs.msg import LaserScan

from joshua_core.schema import PerceptionPacket
from joshua_runtime.convert.stamp import to_proto_timestamp, to_ros_time

SCAN_KIND = "laser_scan"


def packet_to_laser_scan(packet: PerceptionPacket) -> LaserScan:
    """The packet's scan as a LaserScan stamped with the packet's timestamp and frame."""
    sensor = packet.sensor
    if sensor.kind != SCAN_KIND:
        raise ValueError(f"expected a {SCAN_KIND!r} packet, got {sensor.kind!r}")
    message = LaserScan()
    message.header.stamp = to_ros_time(packet.timestamp)
    message.header.frame_id = packet.frame_id
    message.angle_min = sensor.angle_min
    message.angle_max = sensor.angle_max
    message.angle_increment = sensor.angle_increment
    message.time_increment = sensor.time_increment
    message.scan_time = sensor.scan_time
    message.range_min = sensor.range_min
    message.range_max = sensor.range_max
    message.ranges = list(sensor.ranges)
    message.intensities = list(sensor.intensities)
    return message


def laser_scan_to_packet(message: LaserScan) -> PerceptionPacket:
    packet = PerceptionPacket(frame_id=message.header.frame_id)
    to_proto_timestamp(message.header.stamp, packet.timestamp)
    sensor = packet.sensor
    sensor.kind = SCAN_KIND
    sensor.angle_min = message.angle_min
    sensor.angle_max = message.angle_max
    sensor.angle_increment = message.angle_increment
    sensor.time_increment = message.time_increment
    sensor.scan_time = message.scan_time
    sensor.range_min = message.range_min
    sensor.range_max = message.range_max
    sensor.ranges.extend(message.ranges)
    sensor.intensities.extend(message.intensities)
    return packet
