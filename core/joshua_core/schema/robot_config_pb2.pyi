from google.protobuf.internal import containers as _containers
from google.protobuf.internal import enum_type_wrapper as _enum_type_wrapper
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from collections.abc import Iterable as _Iterable, Mapping as _Mapping
from typing import ClassVar as _ClassVar, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor

class Mode(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    MODE_UNSPECIFIED: _ClassVar[Mode]
    MODE_TELEOPERATION: _ClassVar[Mode]
    MODE_SIMULATION: _ClassVar[Mode]
    MODE_INFERENCE: _ClassVar[Mode]
    MODE_DATA_COLLECTION: _ClassVar[Mode]
    MODE_CALIBRATION: _ClassVar[Mode]

class NodeType(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    NODE_TYPE_UNSPECIFIED: _ClassVar[NodeType]
    CAMERA_PUBLISHER: _ClassVar[NodeType]
    ENCODER_PUBLISHER: _ClassVar[NodeType]
    LIDAR_PUBLISHER: _ClassVar[NodeType]
    ACTUATOR_SUBSCRIBER: _ClassVar[NodeType]
    INFERENCE: _ClassVar[NodeType]
    DATA_SUBSCRIBER: _ClassVar[NodeType]
    OPERATIONAL_LIMIT_CALIBRATION: _ClassVar[NodeType]
    MOCK_CAMERA_PUBLISHER: _ClassVar[NodeType]
    MOCK_ENCODER_PUBLISHER: _ClassVar[NodeType]
    MOCK_LIDAR_PUBLISHER: _ClassVar[NodeType]
    MOCK_ACTUATOR_SUBSCRIBER: _ClassVar[NodeType]
    CUSTOM: _ClassVar[NodeType]
    DIFF_DRIVE_BASE: _ClassVar[NodeType]
    MOCK_DIFF_DRIVE_BASE: _ClassVar[NodeType]
    ROBOT_STATE_PUBLISHER: _ClassVar[NodeType]

class Reliability(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    RELIABILITY_UNSPECIFIED: _ClassVar[Reliability]
    BEST_EFFORT: _ClassVar[Reliability]
    RELIABLE: _ClassVar[Reliability]

class Durability(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    DURABILITY_UNSPECIFIED: _ClassVar[Durability]
    VOLATILE: _ClassVar[Durability]
    TRANSIENT_LOCAL: _ClassVar[Durability]

class History(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    HISTORY_UNSPECIFIED: _ClassVar[History]
    KEEP_LAST: _ClassVar[History]
    KEEP_ALL: _ClassVar[History]

class Backend(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    BACKEND_UNSPECIFIED: _ClassVar[Backend]
    CPP: _ClassVar[Backend]
    PYTHON: _ClassVar[Backend]

class Restart(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    RESTART_UNSPECIFIED: _ClassVar[Restart]
    RESTART_NEVER: _ClassVar[Restart]
    RESTART_ON_FAILURE: _ClassVar[Restart]
    RESTART_ALWAYS: _ClassVar[Restart]

class Units(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    UNITS_UNSPECIFIED: _ClassVar[Units]
    SI: _ClassVar[Units]
    LEROBOT: _ClassVar[Units]
    LEROBOT_RANGE: _ClassVar[Units]

class CommandTimeoutAction(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    COMMAND_TIMEOUT_ACTION_UNSPECIFIED: _ClassVar[CommandTimeoutAction]
    HOLD_POSITION: _ClassVar[CommandTimeoutAction]
    RELEASE_TORQUE: _ClassVar[CommandTimeoutAction]
MODE_UNSPECIFIED: Mode
MODE_TELEOPERATION: Mode
MODE_SIMULATION: Mode
MODE_INFERENCE: Mode
MODE_DATA_COLLECTION: Mode
MODE_CALIBRATION: Mode
NODE_TYPE_UNSPECIFIED: NodeType
CAMERA_PUBLISHER: NodeType
ENCODER_PUBLISHER: NodeType
LIDAR_PUBLISHER: NodeType
ACTUATOR_SUBSCRIBER: NodeType
INFERENCE: NodeType
DATA_SUBSCRIBER: NodeType
OPERATIONAL_LIMIT_CALIBRATION: NodeType
MOCK_CAMERA_PUBLISHER: NodeType
MOCK_ENCODER_PUBLISHER: NodeType
MOCK_LIDAR_PUBLISHER: NodeType
MOCK_ACTUATOR_SUBSCRIBER: NodeType
CUSTOM: NodeType
DIFF_DRIVE_BASE: NodeType
MOCK_DIFF_DRIVE_BASE: NodeType
ROBOT_STATE_PUBLISHER: NodeType
RELIABILITY_UNSPECIFIED: Reliability
BEST_EFFORT: Reliability
RELIABLE: Reliability
DURABILITY_UNSPECIFIED: Durability
VOLATILE: Durability
TRANSIENT_LOCAL: Durability
HISTORY_UNSPECIFIED: History
KEEP_LAST: History
KEEP_ALL: History
BACKEND_UNSPECIFIED: Backend
CPP: Backend
PYTHON: Backend
RESTART_UNSPECIFIED: Restart
RESTART_NEVER: Restart
RESTART_ON_FAILURE: Restart
RESTART_ALWAYS: Restart
UNITS_UNSPECIFIED: Units
SI: Units
LEROBOT: Units
LEROBOT_RANGE: Units
COMMAND_TIMEOUT_ACTION_UNSPECIFIED: CommandTimeoutAction
HOLD_POSITION: CommandTimeoutAction
RELEASE_TORQUE: CommandTimeoutAction

class RobotDescription(_message.Message):
    __slots__ = ("robot_config",)
    ROBOT_CONFIG_FIELD_NUMBER: _ClassVar[int]
    robot_config: RobotConfig
    def __init__(self, robot_config: _Optional[_Union[RobotConfig, _Mapping]] = ...) -> None: ...

class Shutdown(_message.Message):
    __slots__ = ("sigint_grace_s", "sigterm_grace_s")
    SIGINT_GRACE_S_FIELD_NUMBER: _ClassVar[int]
    SIGTERM_GRACE_S_FIELD_NUMBER: _ClassVar[int]
    sigint_grace_s: float
    sigterm_grace_s: float
    def __init__(self, sigint_grace_s: _Optional[float] = ..., sigterm_grace_s: _Optional[float] = ...) -> None: ...

class Simulation(_message.Message):
    __slots__ = ("model", "timestep_s", "realtime_factor", "camera", "gl_backend", "host")
    MODEL_FIELD_NUMBER: _ClassVar[int]
    TIMESTEP_S_FIELD_NUMBER: _ClassVar[int]
    REALTIME_FACTOR_FIELD_NUMBER: _ClassVar[int]
    CAMERA_FIELD_NUMBER: _ClassVar[int]
    GL_BACKEND_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    model: str
    timestep_s: float
    realtime_factor: float
    camera: str
    gl_backend: str
    host: str
    def __init__(self, model: _Optional[str] = ..., timestep_s: _Optional[float] = ..., realtime_factor: _Optional[float] = ..., camera: _Optional[str] = ..., gl_backend: _Optional[str] = ..., host: _Optional[str] = ...) -> None: ...

class Foxglove(_message.Message):
    __slots__ = ("port", "bind", "host")
    PORT_FIELD_NUMBER: _ClassVar[int]
    BIND_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    port: int
    bind: str
    host: str
    def __init__(self, port: _Optional[int] = ..., bind: _Optional[str] = ..., host: _Optional[str] = ...) -> None: ...

class RobotConfig(_message.Message):
    __slots__ = ("name", "mode", "node", "shutdown", "simulation", "ros_domain_id", "cpp_bin_dir", "python_executable", "env", "foxglove", "dashboard", "host", "discovery", "control")
    class EnvEntry(_message.Message):
        __slots__ = ("key", "value")
        KEY_FIELD_NUMBER: _ClassVar[int]
        VALUE_FIELD_NUMBER: _ClassVar[int]
        key: str
        value: str
        def __init__(self, key: _Optional[str] = ..., value: _Optional[str] = ...) -> None: ...
    NAME_FIELD_NUMBER: _ClassVar[int]
    MODE_FIELD_NUMBER: _ClassVar[int]
    NODE_FIELD_NUMBER: _ClassVar[int]
    SHUTDOWN_FIELD_NUMBER: _ClassVar[int]
    SIMULATION_FIELD_NUMBER: _ClassVar[int]
    ROS_DOMAIN_ID_FIELD_NUMBER: _ClassVar[int]
    CPP_BIN_DIR_FIELD_NUMBER: _ClassVar[int]
    PYTHON_EXECUTABLE_FIELD_NUMBER: _ClassVar[int]
    ENV_FIELD_NUMBER: _ClassVar[int]
    FOXGLOVE_FIELD_NUMBER: _ClassVar[int]
    DASHBOARD_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    DISCOVERY_FIELD_NUMBER: _ClassVar[int]
    CONTROL_FIELD_NUMBER: _ClassVar[int]
    name: str
    mode: Mode
    node: _containers.RepeatedCompositeFieldContainer[Node]
    shutdown: Shutdown
    simulation: Simulation
    ros_domain_id: int
    cpp_bin_dir: str
    python_executable: str
    env: _containers.ScalarMap[str, str]
    foxglove: Foxglove
    dashboard: Dashboard
    host: _containers.RepeatedCompositeFieldContainer[Host]
    discovery: Discovery
    control: Control
    def __init__(self, name: _Optional[str] = ..., mode: _Optional[_Union[Mode, str]] = ..., node: _Optional[_Iterable[_Union[Node, _Mapping]]] = ..., shutdown: _Optional[_Union[Shutdown, _Mapping]] = ..., simulation: _Optional[_Union[Simulation, _Mapping]] = ..., ros_domain_id: _Optional[int] = ..., cpp_bin_dir: _Optional[str] = ..., python_executable: _Optional[str] = ..., env: _Optional[_Mapping[str, str]] = ..., foxglove: _Optional[_Union[Foxglove, _Mapping]] = ..., dashboard: _Optional[_Union[Dashboard, _Mapping]] = ..., host: _Optional[_Iterable[_Union[Host, _Mapping]]] = ..., discovery: _Optional[_Union[Discovery, _Mapping]] = ..., control: _Optional[_Union[Control, _Mapping]] = ...) -> None: ...

class Host(_message.Message):
    __slots__ = ("name", "address", "ros_from_system", "python")
    NAME_FIELD_NUMBER: _ClassVar[int]
    ADDRESS_FIELD_NUMBER: _ClassVar[int]
    ROS_FROM_SYSTEM_FIELD_NUMBER: _ClassVar[int]
    PYTHON_FIELD_NUMBER: _ClassVar[int]
    name: str
    address: str
    ros_from_system: bool
    python: str
    def __init__(self, name: _Optional[str] = ..., address: _Optional[str] = ..., ros_from_system: _Optional[bool] = ..., python: _Optional[str] = ...) -> None: ...

class Discovery(_message.Message):
    __slots__ = ("server_host", "port")
    SERVER_HOST_FIELD_NUMBER: _ClassVar[int]
    PORT_FIELD_NUMBER: _ClassVar[int]
    server_host: str
    port: int
    def __init__(self, server_host: _Optional[str] = ..., port: _Optional[int] = ...) -> None: ...

class Control(_message.Message):
    __slots__ = ("host", "port", "password_file", "users_file", "tls_ca", "tls_certificate", "tls_private_key")
    HOST_FIELD_NUMBER: _ClassVar[int]
    PORT_FIELD_NUMBER: _ClassVar[int]
    PASSWORD_FILE_FIELD_NUMBER: _ClassVar[int]
    USERS_FILE_FIELD_NUMBER: _ClassVar[int]
    TLS_CA_FIELD_NUMBER: _ClassVar[int]
    TLS_CERTIFICATE_FIELD_NUMBER: _ClassVar[int]
    TLS_PRIVATE_KEY_FIELD_NUMBER: _ClassVar[int]
    host: str
    port: int
    password_file: str
    users_file: str
    tls_ca: str
    tls_certificate: str
    tls_private_key: str
    def __init__(self, host: _Optional[str] = ..., port: _Optional[int] = ..., password_file: _Optional[str] = ..., users_file: _Optional[str] = ..., tls_ca: _Optional[str] = ..., tls_certificate: _Optional[str] = ..., tls_private_key: _Optional[str] = ...) -> None: ...

class Dashboard(_message.Message):
    __slots__ = ("port", "bind", "zenoh_connect", "allowed_host", "zenoh_password_file", "zenoh_tls_ca", "zenoh_tls_certificate", "zenoh_tls_private_key", "host")
    PORT_FIELD_NUMBER: _ClassVar[int]
    BIND_FIELD_NUMBER: _ClassVar[int]
    ZENOH_CONNECT_FIELD_NUMBER: _ClassVar[int]
    ALLOWED_HOST_FIELD_NUMBER: _ClassVar[int]
    ZENOH_PASSWORD_FILE_FIELD_NUMBER: _ClassVar[int]
    ZENOH_TLS_CA_FIELD_NUMBER: _ClassVar[int]
    ZENOH_TLS_CERTIFICATE_FIELD_NUMBER: _ClassVar[int]
    ZENOH_TLS_PRIVATE_KEY_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    port: int
    bind: str
    zenoh_connect: str
    allowed_host: _containers.RepeatedScalarFieldContainer[str]
    zenoh_password_file: str
    zenoh_tls_ca: str
    zenoh_tls_certificate: str
    zenoh_tls_private_key: str
    host: str
    def __init__(self, port: _Optional[int] = ..., bind: _Optional[str] = ..., zenoh_connect: _Optional[str] = ..., allowed_host: _Optional[_Iterable[str]] = ..., zenoh_password_file: _Optional[str] = ..., zenoh_tls_ca: _Optional[str] = ..., zenoh_tls_certificate: _Optional[str] = ..., zenoh_tls_private_key: _Optional[str] = ..., host: _Optional[str] = ...) -> None: ...

class Node(_message.Message):
    __slots__ = ("name", "type", "topic_name", "message_type", "qos_depth", "qos_reliability", "qos_durability", "qos_history", "preferred_backend", "serial_port", "baud_rate", "device_ids", "camera_index", "video_source", "width", "height", "rate_hz", "frame_id", "state_topic", "input_topics", "model_path", "policy_type", "device", "output_format", "output_directory", "restart", "max_restarts", "executable", "args", "calibration_file", "critical", "joint_names", "env", "keep_torque_on_exit", "wheel_radius_m", "track_width_m", "hub", "command_timeout_s", "odom_topic", "ble_transport", "publishes", "subscribes", "bag_max_size_mb", "bag_max_duration_s", "units", "episode_time_s", "reset_time_s", "robot_description", "preset", "on_command_timeout", "diagnostics_rate_hz", "host")
    class EnvEntry(_message.Message):
        __slots__ = ("key", "value")
        KEY_FIELD_NUMBER: _ClassVar[int]
        VALUE_FIELD_NUMBER: _ClassVar[int]
        key: str
        value: str
        def __init__(self, key: _Optional[str] = ..., value: _Optional[str] = ...) -> None: ...
    NAME_FIELD_NUMBER: _ClassVar[int]
    TYPE_FIELD_NUMBER: _ClassVar[int]
    TOPIC_NAME_FIELD_NUMBER: _ClassVar[int]
    MESSAGE_TYPE_FIELD_NUMBER: _ClassVar[int]
    QOS_DEPTH_FIELD_NUMBER: _ClassVar[int]
    QOS_RELIABILITY_FIELD_NUMBER: _ClassVar[int]
    QOS_DURABILITY_FIELD_NUMBER: _ClassVar[int]
    QOS_HISTORY_FIELD_NUMBER: _ClassVar[int]
    PREFERRED_BACKEND_FIELD_NUMBER: _ClassVar[int]
    SERIAL_PORT_FIELD_NUMBER: _ClassVar[int]
    BAUD_RATE_FIELD_NUMBER: _ClassVar[int]
    DEVICE_IDS_FIELD_NUMBER: _ClassVar[int]
    CAMERA_INDEX_FIELD_NUMBER: _ClassVar[int]
    VIDEO_SOURCE_FIELD_NUMBER: _ClassVar[int]
    WIDTH_FIELD_NUMBER: _ClassVar[int]
    HEIGHT_FIELD_NUMBER: _ClassVar[int]
    RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    FRAME_ID_FIELD_NUMBER: _ClassVar[int]
    STATE_TOPIC_FIELD_NUMBER: _ClassVar[int]
    INPUT_TOPICS_FIELD_NUMBER: _ClassVar[int]
    MODEL_PATH_FIELD_NUMBER: _ClassVar[int]
    POLICY_TYPE_FIELD_NUMBER: _ClassVar[int]
    DEVICE_FIELD_NUMBER: _ClassVar[int]
    OUTPUT_FORMAT_FIELD_NUMBER: _ClassVar[int]
    OUTPUT_DIRECTORY_FIELD_NUMBER: _ClassVar[int]
    RESTART_FIELD_NUMBER: _ClassVar[int]
    MAX_RESTARTS_FIELD_NUMBER: _ClassVar[int]
    EXECUTABLE_FIELD_NUMBER: _ClassVar[int]
    ARGS_FIELD_NUMBER: _ClassVar[int]
    CALIBRATION_FILE_FIELD_NUMBER: _ClassVar[int]
    CRITICAL_FIELD_NUMBER: _ClassVar[int]
    JOINT_NAMES_FIELD_NUMBER: _ClassVar[int]
    ENV_FIELD_NUMBER: _ClassVar[int]
    KEEP_TORQUE_ON_EXIT_FIELD_NUMBER: _ClassVar[int]
    WHEEL_RADIUS_M_FIELD_NUMBER: _ClassVar[int]
    TRACK_WIDTH_M_FIELD_NUMBER: _ClassVar[int]
    HUB_FIELD_NUMBER: _ClassVar[int]
    COMMAND_TIMEOUT_S_FIELD_NUMBER: _ClassVar[int]
    ODOM_TOPIC_FIELD_NUMBER: _ClassVar[int]
    BLE_TRANSPORT_FIELD_NUMBER: _ClassVar[int]
    PUBLISHES_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIBES_FIELD_NUMBER: _ClassVar[int]
    BAG_MAX_SIZE_MB_FIELD_NUMBER: _ClassVar[int]
    BAG_MAX_DURATION_S_FIELD_NUMBER: _ClassVar[int]
    UNITS_FIELD_NUMBER: _ClassVar[int]
    EPISODE_TIME_S_FIELD_NUMBER: _ClassVar[int]
    RESET_TIME_S_FIELD_NUMBER: _ClassVar[int]
    ROBOT_DESCRIPTION_FIELD_NUMBER: _ClassVar[int]
    PRESET_FIELD_NUMBER: _ClassVar[int]
    ON_COMMAND_TIMEOUT_FIELD_NUMBER: _ClassVar[int]
    DIAGNOSTICS_RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    name: str
    type: NodeType
    topic_name: str
    message_type: str
    qos_depth: int
    qos_reliability: Reliability
    qos_durability: Durability
    qos_history: History
    preferred_backend: Backend
    serial_port: str
    baud_rate: int
    device_ids: _containers.RepeatedScalarFieldContainer[int]
    camera_index: int
    video_source: str
    width: int
    height: int
    rate_hz: float
    frame_id: str
    state_topic: str
    input_topics: _containers.RepeatedScalarFieldContainer[str]
    model_path: str
    policy_type: str
    device: str
    output_format: str
    output_directory: str
    restart: Restart
    max_restarts: int
    executable: str
    args: _containers.RepeatedScalarFieldContainer[str]
    calibration_file: str
    critical: bool
    joint_names: _containers.RepeatedScalarFieldContainer[str]
    env: _containers.ScalarMap[str, str]
    keep_torque_on_exit: bool
    wheel_radius_m: float
    track_width_m: float
    hub: str
    command_timeout_s: float
    odom_topic: str
    ble_transport: str
    publishes: _containers.RepeatedCompositeFieldContainer[TopicDeclaration]
    subscribes: _containers.RepeatedCompositeFieldContainer[TopicDeclaration]
    bag_max_size_mb: int
    bag_max_duration_s: float
    units: Units
    episode_time_s: float
    reset_time_s: float
    robot_description: str
    preset: _containers.RepeatedCompositeFieldContainer[Preset]
    on_command_timeout: CommandTimeoutAction
    diagnostics_rate_hz: float
    host: str
    def __init__(self, name: _Optional[str] = ..., type: _Optional[_Union[NodeType, str]] = ..., topic_name: _Optional[str] = ..., message_type: _Optional[str] = ..., qos_depth: _Optional[int] = ..., qos_reliability: _Optional[_Union[Reliability, str]] = ..., qos_durability: _Optional[_Union[Durability, str]] = ..., qos_history: _Optional[_Union[History, str]] = ..., preferred_backend: _Optional[_Union[Backend, str]] = ..., serial_port: _Optional[str] = ..., baud_rate: _Optional[int] = ..., device_ids: _Optional[_Iterable[int]] = ..., camera_index: _Optional[int] = ..., video_source: _Optional[str] = ..., width: _Optional[int] = ..., height: _Optional[int] = ..., rate_hz: _Optional[float] = ..., frame_id: _Optional[str] = ..., state_topic: _Optional[str] = ..., input_topics: _Optional[_Iterable[str]] = ..., model_path: _Optional[str] = ..., policy_type: _Optional[str] = ..., device: _Optional[str] = ..., output_format: _Optional[str] = ..., output_directory: _Optional[str] = ..., restart: _Optional[_Union[Restart, str]] = ..., max_restarts: _Optional[int] = ..., executable: _Optional[str] = ..., args: _Optional[_Iterable[str]] = ..., calibration_file: _Optional[str] = ..., critical: _Optional[bool] = ..., joint_names: _Optional[_Iterable[str]] = ..., env: _Optional[_Mapping[str, str]] = ..., keep_torque_on_exit: _Optional[bool] = ..., wheel_radius_m: _Optional[float] = ..., track_width_m: _Optional[float] = ..., hub: _Optional[str] = ..., command_timeout_s: _Optional[float] = ..., odom_topic: _Optional[str] = ..., ble_transport: _Optional[str] = ..., publishes: _Optional[_Iterable[_Union[TopicDeclaration, _Mapping]]] = ..., subscribes: _Optional[_Iterable[_Union[TopicDeclaration, _Mapping]]] = ..., bag_max_size_mb: _Optional[int] = ..., bag_max_duration_s: _Optional[float] = ..., units: _Optional[_Union[Units, str]] = ..., episode_time_s: _Optional[float] = ..., reset_time_s: _Optional[float] = ..., robot_description: _Optional[str] = ..., preset: _Optional[_Iterable[_Union[Preset, _Mapping]]] = ..., on_command_timeout: _Optional[_Union[CommandTimeoutAction, str]] = ..., diagnostics_rate_hz: _Optional[float] = ..., host: _Optional[str] = ...) -> None: ...

class TopicDeclaration(_message.Message):
    __slots__ = ("topic_name", "message_type", "qos_depth", "qos_reliability", "qos_durability", "qos_history")
    TOPIC_NAME_FIELD_NUMBER: _ClassVar[int]
    MESSAGE_TYPE_FIELD_NUMBER: _ClassVar[int]
    QOS_DEPTH_FIELD_NUMBER: _ClassVar[int]
    QOS_RELIABILITY_FIELD_NUMBER: _ClassVar[int]
    QOS_DURABILITY_FIELD_NUMBER: _ClassVar[int]
    QOS_HISTORY_FIELD_NUMBER: _ClassVar[int]
    topic_name: str
    message_type: str
    qos_depth: int
    qos_reliability: Reliability
    qos_durability: Durability
    qos_history: History
    def __init__(self, topic_name: _Optional[str] = ..., message_type: _Optional[str] = ..., qos_depth: _Optional[int] = ..., qos_reliability: _Optional[_Union[Reliability, str]] = ..., qos_durability: _Optional[_Union[Durability, str]] = ..., qos_history: _Optional[_Union[History, str]] = ...) -> None: ...

class Preset(_message.Message):
    __slots__ = ("name", "joint")
    NAME_FIELD_NUMBER: _ClassVar[int]
    JOINT_FIELD_NUMBER: _ClassVar[int]
    name: str
    joint: _containers.RepeatedCompositeFieldContainer[PresetJoint]
    def __init__(self, name: _Optional[str] = ..., joint: _Optional[_Iterable[_Union[PresetJoint, _Mapping]]] = ...) -> None: ...

class PresetJoint(_message.Message):
    __slots__ = ("name", "position")
    NAME_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    name: str
    position: float
    def __init__(self, name: _Optional[str] = ..., position: _Optional[float] = ...) -> None: ...
