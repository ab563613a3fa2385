"""protobuf Timestamp <-> builtin_interfaces/Time, shared by the packet/ROS conversions."""

from builtin_interfaces.msg import Time
from google.protobuf.timestamp_pb2 import Timestamp


def to_ros_time(timestamp: Timestamp) -> Time:
    return Time(sec=timestamp.seconds, nanosec=timestamp.nanos)


def to_proto_timestamp(stamp: Time, timestamp: Timestamp) -> None:
    """Write `stamp` into the packet's `timestamp` field."""
    timestamp.seconds = stamp.sec
    timestamp.nanos = stamp.nanosec
