"""Python classes generated from proto/joshua/v1 (run `make proto` after editing the .proto files).

Each class is imported from its module on first use, so a tool that reads descriptions does not pay
for the packet modules (and google.protobuf's well-known types) it never touches.
"""

import importlib

_MODULES = {
    "ActionPacket": "action_packet_pb2",
    "FleetConfig": "fleet_config_pb2",
    "FleetDescription": "fleet_config_pb2",
    "FleetHost": "fleet_config_pb2",
    "FleetRobot": "fleet_config_pb2",
    "ImageData": "perception_packet_pb2",
    "PerceptionPacket": "perception_packet_pb2",
    "PointCloudData": "perception_packet_pb2",
    "PositionData": "perception_packet_pb2",
    "SensorData": "perception_packet_pb2",
    "Node": "robot_config_pb2",
    "RobotConfig": "robot_config_pb2",
    "RobotDescription": "robot_config_pb2",
}

__all__ = sorted(_MODULES)


def __getattr__(name: str):
    module = _MODULES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value
