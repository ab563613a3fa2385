"""Errors the runtime reports as one clear line instead of a traceback."""


class JoshuaError(Exception):
    """A failure with a message meant for the robot operator."""

    exit_code = 1


class DeviceError(JoshuaError):
    """A device is missing, cannot be opened, or stopped answering."""

    exit_code = 3


class SettingsError(JoshuaError):
    """The settings handed to a node are unusable (a compiler/runtime mismatch)."""

    exit_code = 2
