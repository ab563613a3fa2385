"""Errors the runtime reports as one clear line instead of a traceback."""

from joshua_core.exit_codes import NODE_EXIT_DATA_LOST, NODE_EXIT_DEVICE, NODE_EXIT_FAILURE, NODE_EXIT_SETTINGS


class JoshuaError(Exception):
    """A failure with a message meant for the robot operator."""

    exit_code = NODE_EXIT_FAILURE


class DeviceError(JoshuaError):
    """A device is missing, cannot be opened, or stopped answering."""

    exit_code = NODE_EXIT_DEVICE


class SettingsError(JoshuaError):
    """The settings handed to a node are unusable (a compiler/runtime mismatch)."""

    exit_code = NODE_EXIT_SETTINGS


class DataLostError(JoshuaError):
    """Data the node had taken in could not be saved; the message says what was lost and where."""

    exit_code = NODE_EXIT_DATA_LOST
