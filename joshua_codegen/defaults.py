"""The defaults of every unset field, per node type: the one place both rules and model read them."""

from joshua_core import servo_topics
from joshua_core.message_types import JOINT_STATE, ODOMETRY
from joshua_core.models import DEVICES, GL_BACKENDS, OUTPUT_FORMATS
from joshua_core.node_families import Family, TopicRole
from joshua_core.node_types import BASE_WHEEL_JOINTS, FOXGLOVE_BRIDGE, NODE_TYPES, SIMULATION_ENGINE, NodeTypeSpec
from joshua_core.schema import robot_config_pb2 as pb
from joshua_core.so100 import SO100_JOINTS, SO100_SERVO_IDS

SIGINT_GRACE_S = 5.0
SIGTERM_GRACE_S = 2.0
MAX_RESTARTS = 5
CPP_BIN_DIR = "/opt/joshua/bin"
PYTHON_EXECUTABLE = "python3"
SIMULATION_NAME = SIMULATION_ENGINE.name.lower()
FOXGLOVE_NAME = FOXGLOVE_BRIDGE.name.lower()  # the process name `foxglove { }` reserves (E130)
FOXGLOVE_PORT, FOXGLOVE_BIND = 8765, "0.0.0.0"

NodeType = pb.NodeType
# Node-type numbers of the schema -> registry entries. Every set below is derived from the registry.
SPECS = {pb.NodeType.Value(name): entry for name, entry in NODE_TYPES.items()}
ALL_TYPES = set(SPECS)
_UNTYPED = NodeTypeSpec(name="NODE_TYPE_UNSPECIFIED", family=Family.CUSTOM, topic=TopicRole.NONE)


def _types(predicate) -> set[int]:
    return {number for number, entry in SPECS.items() if predicate(entry)}


CAMERAS = _types(lambda t: t.family == Family.CAMERA)
LIDARS = _types(lambda t: t.family == Family.LIDAR)
ENCODERS = _types(lambda t: t.family == Family.ENCODER)
ACTUATORS = _types(lambda t: t.family == Family.ACTUATOR)
MOCKS = _types(lambda t: bool(t.mock_of))
# Types that read an STS3215 servo bus (real ones), and every type that opens a serial port.
SERVO_BUS = _types(lambda t: t.servo_bus and not t.mock_of)
SERIAL = _types(lambda t: "serial_port" in t.claims)
# Types without a C++ binary: they run their Python entrypoint (CUSTOM: its executable) whatever
# preferred_backend says (W102).
ALWAYS_PYTHON = _types(lambda t: not t.binary)
# Node types that touch hardware; MODE_SIMULATION replaces them with the simulation engine.
HARDWARE = _types(lambda t: t.hardware)
# Node types that publish topic_name, and those that subscribe to it (CUSTOM declares neither).
PUBLISHES_TOPIC = _types(lambda t: t.topic == TopicRole.PUBLISHES)
SUBSCRIBES_TOPIC = _types(lambda t: t.topic == TopicRole.SUBSCRIBES)
READS_INPUTS = _types(lambda t: t.reads_inputs)
# Message types each node type may use on topic_name; the first is the default.
MESSAGE_TYPES = {number: entry.message_types for number, entry in SPECS.items() if entry.message_types}
STATE_MESSAGE_TYPE = JOINT_STATE
ODOM_MESSAGE_TYPE = ODOMETRY
BASES = _types(lambda t: t.family == Family.BASE)
# Node fields that only some node types read; every other type ignores them (W101).
FIELD_APPLIES_TO = {
    name: _types(lambda t, name=name: name in t.fields)
    for name in sorted(set().union(*(entry.fields for entry in SPECS.values())))
}
# Values a few string fields accept (OUTPUT_FORMATS, DEVICES: the first is the default), and defaults.
CAMERA_WIDTH, CAMERA_HEIGHT = 640, 480
# A LEGO car: 56 mm wheels, 12 cm apart; the wheels stop half a second after the last Twist.
WHEEL_RADIUS_M, TRACK_WIDTH_M, COMMAND_TIMEOUT_S = 0.028, 0.12, 0.5
HUB_NAME = "Pybricks Hub"
ODOM_TOPIC = "/odom"
REALTIME_FACTOR = 1.0
DIAGNOSTICS_RATE_HZ = servo_topics.DIAGNOSTICS_RATE_HZ


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


def entry(node: pb.Node) -> NodeTypeSpec:
    """The registry entry of the node's type (a neutral one while the type is unset)."""
    return SPECS.get(node.type, _UNTYPED)


def message_type(node: pb.Node) -> str:
    """The node's message type, or its type's default ("" when the type has none)."""
    return node.message_type or MESSAGE_TYPES.get(node.type, ("",))[0]


def qos(node: pb.Node) -> dict:
    """The node's resolved QoS: `{"history", "depth", "reliability", "durability"}`."""
    return resolved_qos(node, entry(node).sensor_qos)


def resolved_qos(holder: pb.Node | pb.TopicDeclaration, sensor: bool = False) -> dict:
    """The QoS of a message holding qos_* fields (a node, or a topic a CUSTOM node declares)."""
    history = pb.History.Name(holder.qos_history) if holder.qos_history else "KEEP_LAST"
    if holder.HasField("qos_depth"):
        depth = holder.qos_depth
    else:
        depth = 0 if history == "KEEP_ALL" else (5 if sensor else 10)
    if holder.qos_reliability:
        reliability = pb.Reliability.Name(holder.qos_reliability)
    else:
        reliability = "BEST_EFFORT" if sensor else "RELIABLE"
    durability = pb.Durability.Name(holder.qos_durability) if holder.qos_durability else "VOLATILE"
    return {"history": history, "depth": depth, "reliability": reliability, "durability": durability}


def on_command_timeout(node: pb.Node) -> str:
    """What an actuator's command watchdog does: HOLD_POSITION unless the node says RELEASE_TORQUE."""
    return pb.CommandTimeoutAction.Name(node.on_command_timeout or pb.HOLD_POSITION)


def diagnostics_rate_hz(node: pb.Node) -> float:
    return node.diagnostics_rate_hz if node.HasField("diagnostics_rate_hz") else DIAGNOSTICS_RATE_HZ


def baud_rate(node: pb.Node) -> int:
    return node.baud_rate if node.HasField("baud_rate") else entry(node).baud_rate


def device_ids(node: pb.Node) -> list[int]:
    if node.device_ids:
        return list(node.device_ids)
    return list(SO100_SERVO_IDS) if entry(node).servo_bus else []


def joint_names(node: pb.Node) -> list[str]:
    if node.joint_names:
        return list(node.joint_names)
    if node.type in BASES:
        return list(BASE_WHEEL_JOINTS)
    ids = device_ids(node)
    if len(ids) == len(SO100_JOINTS):
        return list(SO100_JOINTS)
    return [f"joint_{i}" for i in ids]


def wheel_radius_m(node: pb.Node) -> float:
    return node.wheel_radius_m if node.HasField("wheel_radius_m") else WHEEL_RADIUS_M


def track_width_m(node: pb.Node) -> float:
    return node.track_width_m if node.HasField("track_width_m") else TRACK_WIDTH_M


def command_timeout_s(node: pb.Node) -> float:
    """A base stops after COMMAND_TIMEOUT_S without a Twist; an arm's watchdog is off (0) unless set."""
    if node.HasField("command_timeout_s"):
        return node.command_timeout_s
    return 0.0 if node.type in ACTUATORS else COMMAND_TIMEOUT_S


def hub(node: pb.Node) -> str:
    return node.hub or HUB_NAME


def odom_topic(node: pb.Node) -> str:
    return node.odom_topic or ODOM_TOPIC


def rate_hz(node: pb.Node) -> float:
    return node.rate_hz if node.HasField("rate_hz") else entry(node).rate_hz


def frame_id(node: pb.Node) -> str:
    return node.frame_id or entry(node).frame_id


def camera_index(node: pb.Node) -> int:
    return node.camera_index if node.HasField("camera_index") else 0


def width(node: pb.Node) -> int:
    return node.width if node.HasField("width") else CAMERA_WIDTH


def height(node: pb.Node) -> int:
    return node.height if node.HasField("height") else CAMERA_HEIGHT


def device(node: pb.Node) -> str:
    return node.device or DEVICES[0]


def output_format(node: pb.Node) -> str:
    return node.output_format or OUTPUT_FORMATS[0]


def units(node: pb.Node) -> str:
    """The convention of a recorder's joint values: SI unless the node says LEROBOT or LEROBOT_RANGE."""
    return pb.Units.Name(node.units or pb.SI)


def realtime_factor(simulation: pb.Simulation) -> float:
    return simulation.realtime_factor if simulation.HasField("realtime_factor") else REALTIME_FACTOR


def gl_backend(simulation: pb.Simulation) -> str:
    return simulation.gl_backend or GL_BACKENDS[0]


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
