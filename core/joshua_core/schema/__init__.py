"""Python classes generated from proto/joshua/v1 (run `make proto` after editing the .proto files)."""
from joshua_core.schema.action_packet_pb2 import ActionPacket
from joshua_core.schema.perception_packet_pb2 import (
    ImageData,
    PerceptionPacket,
    PointCloudData,
    PositionData,
    SensorData,
)
from joshua_core.schema.robot_config_pb2 import Node, RobotConfig, RobotDescription

__all__ = [
    "ActionPacket",
    "ImageData",
    "Node",
    "PerceptionPacket",
    "PointCloudData",
    "PositionData",
    "RobotConfig",
    "RobotDescription",
    "SensorData",
]
