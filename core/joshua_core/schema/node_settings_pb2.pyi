from google.protobuf.internal import containers as _containers
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from collections.abc import Iterable as _Iterable, Mapping as _Mapping
from typing import ClassVar as _ClassVar, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor

class QosSettings(_message.Message):
    __slots__ = ("history", "depth", "reliability", "durability")
    HISTORY_FIELD_NUMBER: _ClassVar[int]
    DEPTH_FIELD_NUMBER: _ClassVar[int]
    RELIABILITY_FIELD_NUMBER: _ClassVar[int]
    DURABILITY_FIELD_NUMBER: _ClassVar[int]
    history: str
    depth: int
    reliability: str
    durability: str
    def __init__(self, history: _Optional[str] = ..., depth: _Optional[int] = ..., reliability: _Optional[str] = ..., durability: _Optional[str] = ...) -> None: ...

class TopicSettings(_message.Message):
    __slots__ = ("name", "message_type", "qos")
    NAME_FIELD_NUMBER: _ClassVar[int]
    MESSAGE_TYPE_FIELD_NUMBER: _ClassVar[int]
    QOS_FIELD_NUMBER: _ClassVar[int]
    name: str
    message_type: str
    qos: QosSettings
    def __init__(self, name: _Optional[str] = ..., message_type: _Optional[str] = ..., qos: _Optional[_Union[QosSettings, _Mapping]] = ...) -> None: ...

class SimulationSettings(_message.Message):
    __slots__ = ("model", "timestep_s", "realtime_factor", "camera", "gl_backend", "simulates")
    MODEL_FIELD_NUMBER: _ClassVar[int]
    TIMESTEP_S_FIELD_NUMBER: _ClassVar[int]
    REALTIME_FACTOR_FIELD_NUMBER: _ClassVar[int]
    CAMERA_FIELD_NUMBER: _ClassVar[int]
    GL_BACKEND_FIELD_NUMBER: _ClassVar[int]
    SIMULATES_FIELD_NUMBER: _ClassVar[int]
    model: str
    timestep_s: float
    realtime_factor: float
    camera: str
    gl_backend: str
    simulates: _containers.RepeatedCompositeFieldContainer[NodeSettings]
    def __init__(self, model: _Optional[str] = ..., timestep_s: _Optional[float] = ..., realtime_factor: _Optional[float] = ..., camera: _Optional[str] = ..., gl_backend: _Optional[str] = ..., simulates: _Optional[_Iterable[_Union[NodeSettings, _Mapping]]] = ...) -> None: ...

class FoxgloveSettings(_message.Message):
    __slots__ = ("port", "host")
    PORT_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    port: int
    host: str
    def __init__(self, port: _Optional[int] = ..., host: _Optional[str] = ...) -> None: ...

class NodeSettings(_message.Message):
    __slots__ = ("format_version", "robot", "mode", "name", "type", "topic", "state_topic", "inputs", "qos", "serial_port", "baud_rate", "device_ids", "joint_names", "calibration_file", "keep_torque_on_exit", "camera_index", "video_source", "width", "height", "rate_hz", "frame_id", "model_path", "policy_type", "device", "output_format", "output_directory", "simulation", "wheel_radius_m", "track_width_m", "hub", "command_timeout_s", "odom_topic", "ble_transport", "bag_max_size_mb", "bag_max_duration_s", "units", "episode_time_s", "reset_time_s", "robot_description", "foxglove", "compressed_topic", "preset", "on_command_timeout", "diagnostics_rate_hz")
    FORMAT_VERSION_FIELD_NUMBER: _ClassVar[int]
    ROBOT_FIELD_NUMBER: _ClassVar[int]
    MODE_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    TYPE_FIELD_NUMBER: _ClassVar[int]
    TOPIC_FIELD_NUMBER: _ClassVar[int]
    STATE_TOPIC_FIELD_NUMBER: _ClassVar[int]
    INPUTS_FIELD_NUMBER: _ClassVar[int]
    QOS_FIELD_NUMBER: _ClassVar[int]
    SERIAL_PORT_FIELD_NUMBER: _ClassVar[int]
    BAUD_RATE_FIELD_NUMBER: _ClassVar[int]
    DEVICE_IDS_FIELD_NUMBER: _ClassVar[int]
    JOINT_NAMES_FIELD_NUMBER: _ClassVar[int]
    CALIBRATION_FILE_FIELD_NUMBER: _ClassVar[int]
    KEEP_TORQUE_ON_EXIT_FIELD_NUMBER: _ClassVar[int]
    CAMERA_INDEX_FIELD_NUMBER: _ClassVar[int]
    VIDEO_SOURCE_FIELD_NUMBER: _ClassVar[int]
    WIDTH_FIELD_NUMBER: _ClassVar[int]
    HEIGHT_FIELD_NUMBER: _ClassVar[int]
    RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    FRAME_ID_FIELD_NUMBER: _ClassVar[int]
    MODEL_PATH_FIELD_NUMBER: _ClassVar[int]
    POLICY_TYPE_FIELD_NUMBER: _ClassVar[int]
    DEVICE_FIELD_NUMBER: _ClassVar[int]
    OUTPUT_FORMAT_FIELD_NUMBER: _ClassVar[int]
    OUTPUT_DIRECTORY_FIELD_NUMBER: _ClassVar[int]
    SIMULATION_FIELD_NUMBER: _ClassVar[int]
    WHEEL_RADIUS_M_FIELD_NUMBER: _ClassVar[int]
    TRACK_WIDTH_M_FIELD_NUMBER: _ClassVar[int]
    HUB_FIELD_NUMBER: _ClassVar[int]
    COMMAND_TIMEOUT_S_FIELD_NUMBER: _ClassVar[int]
    ODOM_TOPIC_FIELD_NUMBER: _ClassVar[int]
    BLE_TRANSPORT_FIELD_NUMBER: _ClassVar[int]
    BAG_MAX_SIZE_MB_FIELD_NUMBER: _ClassVar[int]
    BAG_MAX_DURATION_S_FIELD_NUMBER: _ClassVar[int]
    UNITS_FIELD_NUMBER: _ClassVar[int]
    EPISODE_TIME_S_FIELD_NUMBER: _ClassVar[int]
    RESET_TIME_S_FIELD_NUMBER: _ClassVar[int]
    ROBOT_DESCRIPTION_FIELD_NUMBER: _ClassVar[int]
    FOXGLOVE_FIELD_NUMBER: _ClassVar[int]
    COMPRESSED_TOPIC_FIELD_NUMBER: _ClassVar[int]
    PRESET_FIELD_NUMBER: _ClassVar[int]
    ON_COMMAND_TIMEOUT_FIELD_NUMBER: _ClassVar[int]
    DIAGNOSTICS_RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    format_version: int
    robot: str
    mode: str
    name: str
    type: str
    topic: TopicSettings
    state_topic: TopicSettings
    inputs: _containers.RepeatedCompositeFieldContainer[TopicSettings]
    qos: QosSettings
    serial_port: str
    baud_rate: int
    device_ids: _containers.RepeatedScalarFieldContainer[int]
    joint_names: _containers.RepeatedScalarFieldContainer[str]
    calibration_file: str
    keep_torque_on_exit: bool
    camera_index: int
    video_source: str
    width: int
    height: int
    rate_hz: float
    frame_id: str
    model_path: str
    policy_type: str
    device: str
    output_format: str
    output_directory: str
    simulation: SimulationSettings
    wheel_radius_m: float
    track_width_m: float
    hub: str
    command_timeout_s: float
    odom_topic: TopicSettings
    ble_transport: str
    bag_max_size_mb: int
    bag_max_duration_s: float
    units: str
    episode_time_s: float
    reset_time_s: float
    robot_description: str
    foxglove: FoxgloveSettings
    compressed_topic: TopicSettings
    preset: _containers.RepeatedCompositeFieldContainer[PresetSettings]
    on_command_timeout: str
    diagnostics_rate_hz: float
    def __init__(self, format_version: _Optional[int] = ..., robot: _Optional[str] = ..., mode: _Optional[str] = ..., name: _Optional[str] = ..., type: _Optional[str] = ..., topic: _Optional[_Union[TopicSettings, _Mapping]] = ..., state_topic: _Optional[_Union[TopicSettings, _Mapping]] = ..., inputs: _Optional[_Iterable[_Union[TopicSettings, _Mapping]]] = ..., qos: _Optional[_Union[QosSettings, _Mapping]] = ..., serial_port: _Optional[str] = ..., baud_rate: _Optional[int] = ..., device_ids: _Optional[_Iterable[int]] = ..., joint_names: _Optional[_Iterable[str]] = ..., calibration_file: _Optional[str] = ..., keep_torque_on_exit: _Optional[bool] = ..., camera_index: _Optional[int] = ..., video_source: _Optional[str] = ..., width: _Optional[int] = ..., height: _Optional[int] = ..., rate_hz: _Optional[float] = ..., frame_id: _Optional[str] = ..., model_path: _Optional[str] = ..., policy_type: _Optional[str] = ..., device: _Optional[str] = ..., output_format: _Optional[str] = ..., output_directory: _Optional[str] = ..., simulation: _Optional[_Union[SimulationSettings, _Mapping]] = ..., wheel_radius_m: _Optional[float] = ..., track_width_m: _Optional[float] = ..., hub: _Optional[str] = ..., command_timeout_s: _Optional[float] = ..., odom_topic: _Optional[_Union[TopicSettings, _Mapping]] = ..., ble_transport: _Optional[str] = ..., bag_max_size_mb: _Optional[int] = ..., bag_max_duration_s: _Optional[float] = ..., units: _Optional[str] = ..., episode_time_s: _Optional[float] = ..., reset_time_s: _Optional[float] = ..., robot_description: _Optional[str] = ..., foxglove: _Optional[_Union[FoxgloveSettings, _Mapping]] = ..., compressed_topic: _Optional[_Union[TopicSettings, _Mapping]] = ..., preset: _Optional[_Iterable[_Union[PresetSettings, _Mapping]]] = ..., on_command_timeout: _Optional[str] = ..., diagnostics_rate_hz: _Optional[float] = ...) -> None: ...

class PresetSettings(_message.Message):
    __slots__ = ("name", "positions")
    class PositionsEntry(_message.Message):
        __slots__ = ("key", "value")
        KEY_FIELD_NUMBER: _ClassVar[int]
        VALUE_FIELD_NUMBER: _ClassVar[int]
        key: str
        value: float
        def __init__(self, key: _Optional[str] = ..., value: _Optional[float] = ...) -> None: ...
    NAME_FIELD_NUMBER: _ClassVar[int]
    POSITIONS_FIELD_NUMBER: _ClassVar[int]
    name: str
    positions: _containers.ScalarMap[str, float]
    def __init__(self, name: _Optional[str] = ..., positions: _Optional[_Mapping[str, float]] = ...) -> None: ...
