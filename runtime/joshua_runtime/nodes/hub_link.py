"""The LEGO base's Bluetooth link as an operator sees it: log lines, /diagnostics, and exit code 3 when it stays down.

The driver (drivers/pybricks.py) notices a lost link and reconnects on its own; `HubLinkWatch` looks
at it every LINK_CHECK_PERIOD_S from the node's executor. A loss is logged in one line and turns the
node's status on /diagnostics (`<node>: Pybricks hub`) to ERROR at once; the reconnection is logged
and turns it back to OK. A link not back within HUB_RECONNECT_WINDOW_S ends the node with a
DeviceError (exit code 3), so that its supervisor restarts it. The status is published every
1/DIAGNOSTICS_RATE_HZ besides.
"""

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from joshua_core.servo_topics import DIAGNOSTICS_RATE_HZ, DIAGNOSTICS_TOPIC, FIXED_QOS
from joshua_core.settings import QosSettings
from joshua_runtime.drivers.pybricks import HUB_RECONNECT_WINDOW_S, PybricksHub
from joshua_runtime.errors import DeviceError
from joshua_runtime.qos import qos_profile

LINK_CHECK_PERIOD_S = 0.05
STATUS_SUFFIX = ": Pybricks hub"


class HubLinkWatch:
    """Reports the state of `hub`'s link for `node`; calls `on_lost()` once per loss, from the executor."""

    def __init__(self, node, hub: PybricksHub, on_lost):
        self.node, self.hub, self.on_lost = node, hub, on_lost
        self.losses_seen, self.reconnects_seen = hub.link_losses, hub.reconnects
        self.publisher = node.ros.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, qos_profile(QosSettings(**FIXED_QOS))
        )
        node.ros.create_timer(LINK_CHECK_PERIOD_S, self.check)
        node.ros.create_timer(1.0 / DIAGNOSTICS_RATE_HZ, self.publish)
        self.publish()

    def check(self) -> None:
        hub = self.hub
        if hub.link_losses != self.losses_seen:
            self.losses_seen = hub.link_losses
            self.on_lost()
            self.node.log.warning(
                f"link to Pybricks hub {hub.hub!r} lost ({hub.lost_reason}): the hub stops its wheels; "
                f"reconnecting for up to {HUB_RECONNECT_WINDOW_S:g} s"
            )
            self.publish()
        if hub.reconnects != self.reconnects_seen:
            self.reconnects_seen = hub.reconnects
            self.node.log.info(
                f"reconnected to Pybricks hub {hub.hub!r} after {hub.last_outage_s:.1f} s; wheels stopped"
            )
            self.publish()
        lost_for = hub.lost_for()
        if lost_for is not None and lost_for >= HUB_RECONNECT_WINDOW_S:
            raise DeviceError(
                f"link to Pybricks hub {hub.hub!r} lost for {HUB_RECONNECT_WINDOW_S:g} s "
                f"({hub.lost_reason}; last attempt: {hub.last_attempt_error or 'none finished'})"
            )

    def publish(self) -> None:
        message = DiagnosticArray()
        message.header.stamp = self.node.stamp()
        message.status.append(self.status())
        self.publisher.publish(message)

    def status(self) -> DiagnosticStatus:
        hub = self.hub
        lost_for = hub.lost_for()
        if lost_for is None:
            level, text = DiagnosticStatus.OK, "connected"
        else:
            level, text = DiagnosticStatus.ERROR, f"link lost {lost_for:.1f} s ago ({hub.lost_reason}); reconnecting"
            if hub.last_attempt_error:
                text += f": {hub.last_attempt_error}"
        values = {"link_losses": hub.link_losses, "reconnects": hub.reconnects}
        return DiagnosticStatus(
            level=level,
            name=self.node.name + STATUS_SUFFIX,
            hardware_id=hub.hub,
            message=text,
            values=[KeyValue(key=key, value=str(value)) for key, value in values.items()],
        )
