"""What the STS3215 nodes share: a bus driver built from node settings, and riding out a lost port.

`BusGuard.call` runs one bus operation per control tick. While the port is gone it logs (at most
every LOG_INTERVAL_S), lets the driver try to reopen it no more often than every RECONNECT_INTERVAL_S,
and raises DeviceError (exit code 3, the supervisor restarts the node) once the bus has been failing
for DEVICE_LOST_GRACE_S.
"""

import time

from joshua_core.settings import NodeSettings
from joshua_runtime.drivers.calibration import calibration_for_bus
from joshua_runtime.drivers.sts3215 import Sts3215Driver
from joshua_runtime.errors import DeviceError
from joshua_runtime.nodes import settings_checks

DEVICE_LOST_GRACE_S = 3.0
RECONNECT_INTERVAL_S = 0.25
LOG_INTERVAL_S = 1.0


def bus_from_settings(settings: NodeSettings, use_calibration: bool = True) -> Sts3215Driver:
    """An unopened driver for the node's serial_port, baud_rate, device_ids, joint_names and calibration_file."""
    ids, names = settings_checks.joints(settings)
    calibration_file = settings.calibration_file if use_calibration else ""
    calibration = calibration_for_bus(calibration_file, names, ids) if calibration_file else None
    return Sts3215Driver(settings.serial_port, ids, names, baud_rate=settings.baud_rate, calibration=calibration)


class BusGuard:
    """Runs bus operations for a node, tolerating a short loss of the port."""

    def __init__(self, bus: Sts3215Driver, logger, on_reconnect=None):
        self.bus = bus
        self.log = logger
        self.on_reconnect = on_reconnect
        self._connections = bus.connections
        self._failing_since: float | None = None
        self._last_error: DeviceError | None = None
        self._next_attempt = 0.0
        self._next_log = 0.0

    @property
    def last_error(self) -> str:
        """Why the last failing operation failed ("" when none has failed)."""
        return str(self._last_error or "")

    def call(self, operation, *args):
        """The operation's result, or None while the bus is failing."""
        now = time.monotonic()
        if self._failing_since is not None and not self.bus.is_open and now < self._next_attempt:
            self._check_grace(now)
            return None
        try:
            result = operation(*args)
        except DeviceError as exc:
            self._failed(now, exc)
            return None
        if self.bus.connections != self._connections:
            self._connections = self.bus.connections
            self.log.info(f"{self.bus.port}: reconnected")
            if self.on_reconnect is not None:
                self.on_reconnect()
        self._failing_since = None
        return result

    def _failed(self, now: float, exc: DeviceError) -> None:
        if self._failing_since is None:
            self._failing_since = now
        self._last_error = exc
        self._next_attempt = now + RECONNECT_INTERVAL_S
        if now >= self._next_log:
            self._next_log = now + LOG_INTERVAL_S
            self.log.warning(str(exc))
        self._check_grace(now)

    def _check_grace(self, now: float) -> None:
        if now - self._failing_since >= DEVICE_LOST_GRACE_S:
            raise DeviceError(f"{self.bus.port}: bus failing for {DEVICE_LOST_GRACE_S:g} s: {self._last_error}")
