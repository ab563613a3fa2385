"""What a node type is about (its family) and what it does with its topic: the enums the registry's entries hold."""

from enum import Enum


class TextEnum(str, Enum):  # noqa: UP042 (joshua_core runs on Python 3.10, which has no StrEnum)
    """An enum whose members are their text, also in str() and format() (enum.StrEnum, which needs Python 3.11)."""

    def __str__(self) -> str:
        return self.value

    __format__ = str.__format__


class Family(TextEnum):
    """What a node type is about. Behaviour that depends on it compares with these members, never with text."""

    CAMERA = "camera"
    LIDAR = "lidar"
    ENCODER = "encoder"
    ACTUATOR = "actuator"
    CALIBRATION = "calibration"
    INFERENCE = "inference"
    RECORDER = "recorder"
    BASE = "base"
    STATE_PUBLISHER = "state_publisher"
    CUSTOM = "custom"
    SIMULATION = "simulation"
    BRIDGE = "bridge"


class TopicRole(TextEnum):
    """What a node type does with its topic_name (NONE: it has none, CUSTOM declares its topics)."""

    PUBLISHES = "publishes"
    SUBSCRIBES = "subscribes"
    NONE = ""


# The families that read joints through an STS3215 servo bus (or stand in for one that does).
SERVO_BUS_FAMILIES = frozenset({Family.ENCODER, Family.ACTUATOR, Family.CALIBRATION})
