from google.protobuf.internal import containers as _containers
from google.protobuf.internal import enum_type_wrapper as _enum_type_wrapper
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from collections.abc import Iterable as _Iterable, Mapping as _Mapping
from typing import ClassVar as _ClassVar, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor

class StartMethod(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    START_METHOD_UNSPECIFIED: _ClassVar[StartMethod]
    START_SYSTEMD: _ClassVar[StartMethod]
    START_SUPERVISOR: _ClassVar[StartMethod]

class OnFailure(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = ()
    ON_FAILURE_UNSPECIFIED: _ClassVar[OnFailure]
    ON_FAILURE_STOP: _ClassVar[OnFailure]
    ON_FAILURE_CONTINUE: _ClassVar[OnFailure]
START_METHOD_UNSPECIFIED: StartMethod
START_SYSTEMD: StartMethod
START_SUPERVISOR: StartMethod
ON_FAILURE_UNSPECIFIED: OnFailure
ON_FAILURE_STOP: OnFailure
ON_FAILURE_CONTINUE: OnFailure

class FleetDescription(_message.Message):
    __slots__ = ("fleet_config",)
    FLEET_CONFIG_FIELD_NUMBER: _ClassVar[int]
    fleet_config: FleetConfig
    def __init__(self, fleet_config: _Optional[_Union[FleetConfig, _Mapping]] = ...) -> None: ...

class FleetConfig(_message.Message):
    __slots__ = ("name", "robot", "start", "release_key", "rollout")
    NAME_FIELD_NUMBER: _ClassVar[int]
    ROBOT_FIELD_NUMBER: _ClassVar[int]
    START_FIELD_NUMBER: _ClassVar[int]
    RELEASE_KEY_FIELD_NUMBER: _ClassVar[int]
    ROLLOUT_FIELD_NUMBER: _ClassVar[int]
    name: str
    robot: _containers.RepeatedCompositeFieldContainer[FleetRobot]
    start: StartMethod
    release_key: str
    rollout: Rollout
    def __init__(self, name: _Optional[str] = ..., robot: _Optional[_Iterable[_Union[FleetRobot, _Mapping]]] = ..., start: _Optional[_Union[StartMethod, str]] = ..., release_key: _Optional[str] = ..., rollout: _Optional[_Union[Rollout, _Mapping]] = ...) -> None: ...

class Rollout(_message.Message):
    __slots__ = ("canary", "batch", "health_timeout_s", "on_failure")
    CANARY_FIELD_NUMBER: _ClassVar[int]
    BATCH_FIELD_NUMBER: _ClassVar[int]
    HEALTH_TIMEOUT_S_FIELD_NUMBER: _ClassVar[int]
    ON_FAILURE_FIELD_NUMBER: _ClassVar[int]
    canary: int
    batch: int
    health_timeout_s: float
    on_failure: OnFailure
    def __init__(self, canary: _Optional[int] = ..., batch: _Optional[int] = ..., health_timeout_s: _Optional[float] = ..., on_failure: _Optional[_Union[OnFailure, str]] = ...) -> None: ...

class FleetRobot(_message.Message):
    __slots__ = ("name", "description", "address", "set", "ssh_user", "ssh_port", "host")
    NAME_FIELD_NUMBER: _ClassVar[int]
    DESCRIPTION_FIELD_NUMBER: _ClassVar[int]
    ADDRESS_FIELD_NUMBER: _ClassVar[int]
    SET_FIELD_NUMBER: _ClassVar[int]
    SSH_USER_FIELD_NUMBER: _ClassVar[int]
    SSH_PORT_FIELD_NUMBER: _ClassVar[int]
    HOST_FIELD_NUMBER: _ClassVar[int]
    name: str
    description: str
    address: str
    set: _containers.RepeatedScalarFieldContainer[str]
    ssh_user: str
    ssh_port: int
    host: _containers.RepeatedCompositeFieldContainer[FleetHost]
    def __init__(self, name: _Optional[str] = ..., description: _Optional[str] = ..., address: _Optional[str] = ..., set: _Optional[_Iterable[str]] = ..., ssh_user: _Optional[str] = ..., ssh_port: _Optional[int] = ..., host: _Optional[_Iterable[_Union[FleetHost, _Mapping]]] = ...) -> None: ...

class FleetHost(_message.Message):
    __slots__ = ("name", "address")
    NAME_FIELD_NUMBER: _ClassVar[int]
    ADDRESS_FIELD_NUMBER: _ClassVar[int]
    name: str
    address: str
    def __init__(self, name: _Optional[str] = ..., address: _Optional[str] = ...) -> None: ...
