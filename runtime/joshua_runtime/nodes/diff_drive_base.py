"""DIFF_DRIVE_BASE: a two-motor base on a Pybricks hub over Bluetooth LE (see nodes/diff_drive.py for its topics).

The hub is reached through the computer's adapter (bleak), or through a Bumble controller when
ble_transport names one (a USB dongle, or `joshua-emulate pybricks`). When the link drops the driver
reconnects; meanwhile no odometry is published, the hub program stops the wheels on its own, and
the node says so (hub_link.py: a log line, an ERROR on /diagnostics, exit code 3 when the link stays
down for HUB_RECONNECT_WINDOW_S). After a reconnection the wheels wait for the next Twist and
odometry goes on from the pose it had.
"""

import math

from joshua_runtime.drivers.pybricks import PybricksHub
from joshua_runtime.drivers.pybricks_program import program_blob
from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes.diff_drive import BaseTopics, WheelDrive
from joshua_runtime.nodes.hub_link import HubLinkWatch


def hub_transport(ble_transport: str):
    """The BLE transport named by the settings: Bumble over `ble_transport`, else bleak."""
    if ble_transport:
        from joshua_runtime.drivers.pybricks_bumble import BumbleTransport

        return BumbleTransport(hci=ble_transport)
    from joshua_runtime.drivers.pybricks_transport import BleakTransport

    return BleakTransport()


class HubWheels(WheelDrive):
    """The hub program's two motors, in radians."""

    def __init__(self, hub: PybricksHub):
        self.hub = hub

    def set_wheel_speeds(self, left_rad_s: float, right_rad_s: float) -> None:
        self.hub.set_speeds(math.degrees(left_rad_s), math.degrees(right_rad_s))

    def wheel_angles(self):
        report = self.hub.latest
        if report is None or not self.hub.connected:
            return None
        return math.radians(report.left_deg), math.radians(report.right_deg), report.hub_ms / 1000.0


class DiffDriveBase(JoshuaNode):
    hub = None

    def start(self) -> None:
        if not self.settings.hub:
            raise SettingsError("DIFF_DRIVE_BASE needs a hub name or address")
        self.hub = PybricksHub(self.settings.hub, hub_transport(self.settings.ble_transport), program_blob())
        self.hub.open()
        self.log.info(f"connected to Pybricks hub {self.settings.hub!r}, program running")
        self.topics = BaseTopics(self, self.settings, HubWheels(self.hub))
        self.link = HubLinkWatch(self, self.hub, on_lost=self.topics.wheels_lost)

    def close(self) -> None:
        if self.hub is not None:
            self.hub.close()
