"""The runtime's one guard of node settings, each failing with a one-line SettingsError.

joshuac's rules reject every such description before start (E104 topics, E113 rates and sizes, E406
joint counts); these checks catch settings written by hand or by another tool, the same way for every
node type and for the simulated ones.
"""

from joshua_core.settings import NodeSettings, TopicSettings
from joshua_runtime.errors import SettingsError


def topic(settings: NodeSettings, field: str = "topic") -> TopicSettings:
    """The node's topic_name (or state_topic) settings; it must have one."""
    if not settings.HasField(field):
        raise SettingsError(f"{settings.type} needs a {field}")
    return getattr(settings, field)


def period_s(settings: NodeSettings) -> float:
    """Seconds between two ticks at the node's rate_hz, which must be positive."""
    if not settings.rate_hz > 0:
        raise SettingsError(f"rate_hz must be positive, got {settings.rate_hz!r}")
    return 1.0 / settings.rate_hz


def image_size(settings: NodeSettings) -> tuple[int, int]:
    """(width, height) of the node's images, both positive."""
    if settings.width <= 0 or settings.height <= 0:
        raise SettingsError(f"width and height must be positive, got {settings.width}x{settings.height}")
    return settings.width, settings.height


def joints(settings: NodeSettings) -> tuple[list[int], list[str]]:
    """(device_ids, joint_names) of a servo node: ids present, one name per id (`joint_<id>` when unnamed)."""
    ids = list(settings.device_ids)
    if not ids:
        raise SettingsError("device_ids is empty")
    names = list(settings.joint_names) or [f"joint_{i}" for i in ids]
    if len(names) != len(ids):
        raise SettingsError(f"{len(names)} joint_names for {len(ids)} device_ids")
    return ids, names
