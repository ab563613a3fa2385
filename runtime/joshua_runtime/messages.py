"""Resolve `pkg/msg/Type` strings to rclpy message classes."""

import importlib

from joshua_runtime.errors import SettingsError


def message_class(message_type: str):
    """Import the message class named by `pkg/msg/Type`, e.g. `sensor_msgs/msg/Image`."""
    try:
        package, kind, name = message_type.split("/")
        module = importlib.import_module(f"{package}.{kind}")
        return getattr(module, name)
    except (ValueError, ImportError, AttributeError) as exc:
        raise SettingsError(f"message type {message_type!r} is not available: {exc}") from exc
