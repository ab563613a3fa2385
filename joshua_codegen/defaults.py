"""The defaults of every unset field, per node type: the one place both rules and model read them."""

from joshua_core.devices import LDS01_BAUD_RATE, STS3215_BAUD_RATES, STS3215_DEFAULT_BAUD_RATE
from joshua_core.models import BUILTIN_MODELS, BUILTIN_PREFIX, GL_BACKENDS, REGISTRY_PREFIX
from joshua_core.schema import robot_config_pb2 as pb
from joshua_core.so100 import SO100_JOINTS, SO100_SERVO_IDS
SIGINT_GRACE_S = 5.0
SIGTERM_GRACE_S = 2.0
MAX_RESTARTS = 5
CPP_BIN_DIR = "/opt/joshua/bin"
PYTHON_EXECUTABLE = "python3"
SIMULATION_NAME = "simulation"

NodeType = pb.NodeType
CAMERAS = {pb.CAMERA_PUBLISHER, pb.MOCK_CAMERA_PUBLISHER}
LIDARS = {pb.LIDAR_PUBLISHER, pb.MOCK_LIDAR_PUBLISHER}
ENCODERS = {pb.ENCODER_PUBLISHER, pb.MOCK_ENCODER_PUBLISHER}
ACTUATORS = {pb.ACTUATOR_SUBSCRIBER, pb.MOCK_ACTUATOR_SUBSCRIBER}
SERVO_BUS = {pb.ENCODER_PUBLISHER, pb.ACTUATOR_SUBSCRIBER, pb.OPERATIONAL_LIMIT_CALIBRATION}
SERIAL = SERVO_BUS | {pb.LIDAR_PUBLISHER}
MOCKS = {pb.MOCK_CAMERA_PUBLISHER, pb.MOCK_ENCODER_PUBLISHER, pb.MOCK_LIDAR_PUBLISHER, pb.MOCK_ACTUATOR_SUBSCRIBER}
ALWAYS_PYTHON = MOCKS | {pb.INFERENCE, pb.DATA_SUBSCRIBER, pb.CUSTOM}
# Node types that touch hardware; MODE_SIMULATION replaces them with the simulation engine.
HARDWARE = {pb.CAMERA_PUBLISHER, pb.ENCODER_PUBLISHER, pb.LIDAR_PUBLISHER, pb.ACTUATOR_SUBSCRIBER,
            pb.OPERATIONAL_LIMIT_CALIBRATION}
# Node types that publish topic_name (the others subscribe to it; CUSTOM declares nothing).
PUBLISHES_TOPIC = CAMERAS | LIDARS | ENCODERS | {pb.INFERENCE, pb.OPERATIONAL_LIMIT_CALIBRATION}
SUBSCRIBES_TOPIC = ACTUATORS | {pb.DATA_SUBSCRIBER}
# Node types that read input_topics.
READS_INPUTS = {pb.INFERENCE, pb.DATA_SUBSCRIBER}

# Message types each node type may use on topic_name; the first is the default.
MESSAGE_TYPES = {
    pb.CAMERA_PUBLISHER: ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage"),
    pb.MOCK_CAMERA_PUBLISHER: ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage"),
    pb.LIDAR_PUBLISHER: ("sensor_msgs/msg/LaserScan",),
    pb.MOCK_LIDAR_PUBLISHER: ("sensor_msgs/msg/LaserScan",),
    pb.ENCODER_PUBLISHER: ("sensor_msgs/msg/JointState",),
    pb.MOCK_ENCODER_PUBLISHER: ("sensor_msgs/msg/JointState",),
    pb.ACTUATOR_SUBSCRIBER: ("sensor_msgs/msg/JointState",),
    pb.MOCK_ACTUATOR_SUBSCRIBER: ("sensor_msgs/msg/JointState",),
    pb.INFERENCE: ("sensor_msgs/msg/JointState",),
    pb.DATA_SUBSCRIBER: ("sensor_msgs/msg/JointState",),  # recorded as the dataset's action
    pb.OPERATIONAL_LIMIT_CALIBRATION: ("sensor_msgs/msg/JointState",),
}
STATE_MESSAGE_TYPE = "sensor_msgs/msg/JointState"

ALL_TYPES = {value for value in pb.NodeType.values() if value != pb.NODE_TYPE_UNSPECIFIED}
# Node fields that only some node types read (a MOCK_* type reads what its real type reads, so a
# description can switch between them); every other type ignores them. Unlisted fields apply to all.
FIELD_APPLIES_TO = {
    "serial_port": SERIAL | (MOCKS - CAMERAS),
    "baud_rate": SERIAL | (MOCKS - CAMERAS),
    "device_ids": SERVO_BUS | ENCODERS | ACTUATORS,
    "joint_names": SERVO_BUS | ENCODERS | ACTUATORS | {pb.INFERENCE},
    "calibration_file": SERVO_BUS | ENCODERS | ACTUATORS,
    "camera_index": CAMERAS,
    "video_source": CAMERAS,
    "width": CAMERAS,
    "height": CAMERAS,
    "rate_hz": ALL_TYPES - {pb.CUSTOM},
    "frame_id": PUBLISHES_TOPIC | ACTUATORS,
    "state_topic": ACTUATORS,
    "keep_torque_on_exit": {pb.ACTUATOR_SUBSCRIBER},
    "input_topics": READS_INPUTS,
    "model_path": {pb.INFERENCE},
    "policy_type": {pb.INFERENCE},
    "device": {pb.INFERENCE},
    "output_format": {pb.DATA_SUBSCRIBER},
    "output_directory": {pb.DATA_SUBSCRIBER},
    "executable": {pb.CUSTOM},
    "args": {pb.CUSTOM},
}
OUTPUT_FORMATS = ("lerobot", "parquet")
DEVICES = ("cpu", "cuda")


def type_name(node_type: int) -> str:
    """`CAMERA_PUBLISHER` for the enum value (or the number when it has no name)."""
    try:
        return pb.NodeType.Name(node_type)
    except ValueError:
        return str(node_type)


def node_names(config: pb.RobotConfig) -> list[str]:
    """Each node's name: its own, or its type in lower case with `_1`, `_2`... when several lack one."""
    unnamed: dict[int, int] = {}
    for node in config.node:
        if not node.name:
            unnamed[node.type] = unnamed.get(node.type, 0) + 1
    seen: dict[int, int] = {}
    names = []
    for node in config.node:
        if node.name:
            names.append(node.name)
            continue
        base = type_name(node.type).lower()
        if unnamed[node.type] == 1:
            names.append(base)
        else:
            seen[node.type] = seen.get(node.type, 0) + 1
            names.append(f"{base}_{seen[node.type]}")
    return names


def message_type(node: pb.Node) -> str:
    """The node's message type, or its type's default ("" when the type has none)."""
    return node.message_type or MESSAGE_TYPES.get(node.type, ("",))[0]


def qos(node: pb.Node) -> dict:
    """The node's resolved QoS: `{"history", "depth", "reliability", "durability"}`."""
    sensor = node.type in CAMERAS | LIDARS
    history = pb.History.Name(node.qos_history) if node.qos_history else "KEEP_LAST"
    if node.HasField("qos_depth"):
        depth = node.qos_depth
    else:
        depth = 0 if history == "KEEP_ALL" else (5 if sensor else 10)
    if node.qos_reliability:
        reliability = pb.Reliability.Name(node.qos_reliability)
    else:
        reliability = "BEST_EFFORT" if sensor else "RELIABLE"
    durability = pb.Durability.Name(node.qos_durability) if node.qos_durability else "VOLATILE"
    return {"history": history, "depth": depth, "reliability": reliability, "durability": durability}


def baud_rate(node: pb.Node) -> int:
    if node.HasField("baud_rate"):
        return node.baud_rate
    if node.type in LIDARS:
        return LDS01_BAUD_RATE
    return STS3215_DEFAULT_BAUD_RATE if node.type in SERVO_BUS | ACTUATORS | ENCODERS else 0


def device_ids(node: pb.Node) -> list[int]:
    if node.device_ids:
        return list(node.device_ids)
    return list(SO100_SERVO_IDS) if node.type in SERVO_BUS | ACTUATORS | ENCODERS else []


def joint_names(node: pb.Node) -> list[str]:
    if node.joint_names:
        return list(node.joint_names)
    ids = device_ids(node)
    if len(ids) == len(SO100_JOINTS):
        return list(SO100_JOINTS)
    return [f"joint_{i}" for i in ids]


def rate_hz(node: pb.Node) -> float:
    if node.HasField("rate_hz"):
        return node.rate_hz
    if node.type in CAMERAS:
        return 30.0
    if node.type in LIDARS:
        return 5.0
    if node.type in READS_INPUTS:
        return 30.0
    return 100.0


def frame_id(node: pb.Node) -> str:
    if node.frame_id:
        return node.frame_id
    if node.type in CAMERAS:
        return "camera"
    if node.type in LIDARS:
        return "laser"
    return "base_link"


def restart(node: pb.Node) -> str:
    return pb.Restart.Name(node.restart) if node.restart else "RESTART_ON_FAILURE"


def max_restarts(node: pb.Node) -> int:
    return node.max_restarts if node.HasField("max_restarts") else MAX_RESTARTS


def critical(node: pb.Node) -> bool:
    return node.critical if node.HasField("critical") else True


def backend(node: pb.Node) -> str:
    """PYTHON or CPP: the preference, where the node type honours one."""
    if node.type in ALWAYS_PYTHON or node.preferred_backend != pb.CPP:
        return "PYTHON"
    return "CPP"
