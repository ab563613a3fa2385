"""Checks of the settings a sensor node needs, each failing with a one-line SettingsError."""

from joshua_runtime.errors import SettingsError


def topic(settings: dict, key: str = "topic") -> dict:
    value = settings.get(key)
    if not value:
        raise SettingsError(f"{settings['type']} needs a {key}")
    return value


def period_s(settings: dict) -> float:
    rate = settings.get("rate_hz", 0)
    if not rate or rate <= 0:
        raise SettingsError(f"rate_hz must be positive, got {rate!r}")
    return 1.0 / rate


def image_size(settings: dict) -> tuple[int, int]:
    width, height = settings.get("width", 0), settings.get("height", 0)
    if width <= 0 or height <= 0:
        raise SettingsError(f"width and height must be positive, got {width}x{height}")
    return width, height
