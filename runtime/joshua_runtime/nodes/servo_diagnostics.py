"""/diagnostics of the STS3215 nodes: one DiagnosticStatus per servo, every 1/diagnostics_rate_hz.

Each publication costs one SYNC_READ of the telemetry span (Present_Position .. Present_Current) of
every servo, run by the node's BusGuard between two control ticks: at 1 Hz that is one extra bus
transaction a second (bench/servo_diagnostics.py measures it against a control tick). Readings are
judged by drivers/sts3215_health.py (STS3215 limits). A failed read makes every servo ERROR and counts
as a read failure. The node adds its own findings: `note` for one publication (a clamped goal),
`condition` for as long as it holds (a stopped actuator).
"""

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from joshua_core.servo_topics import DIAGNOSTICS_RATE_HZ, DIAGNOSTICS_TOPIC, FIXED_QOS
from joshua_core.settings import QosSettings
from joshua_runtime.drivers.sts3215_health import Finding, assess, level, read_failure
from joshua_runtime.drivers.sts3215_status import ServoStatus, read_status
from joshua_runtime.errors import SettingsError
from joshua_runtime.qos import qos_profile


class ServoDiagnostics:
    """Publishes the health of a node's servos on /diagnostics at the node's diagnostics_rate_hz."""

    def __init__(self, node, guard):
        rate = node.settings.diagnostics_rate_hz or DIAGNOSTICS_RATE_HZ
        if not rate > 0:
            raise SettingsError(f"diagnostics_rate_hz must be positive, got {rate!r}")
        self.node, self.guard, self.bus = node, guard, guard.bus
        self.joints = dict(zip(self.bus.ids, self.bus.joint_names))
        self.read_failures = dict.fromkeys(self.bus.ids, 0)
        self.counters: dict[str, int] = {}
        self.condition: Finding | None = None
        self._notes: dict[int, list[Finding]] = {}
        self.publisher = node.ros.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, qos_profile(QosSettings(**FIXED_QOS))
        )
        self.timer = node.ros.create_timer(1.0 / rate, self.publish)

    def note(self, servo_id: int, finding: Finding) -> None:
        """A finding about one servo, reported in the next publication only."""
        self._notes.setdefault(servo_id, []).append(finding)

    def count(self, name: str, amount: int = 1) -> None:
        """Raise a node counter reported with every servo (e.g. goals_clamped)."""
        self.counters[name] = self.counters.get(name, 0) + amount

    def publish(self) -> None:
        statuses = self.guard.call(read_status, self.bus, self.bus.ids)
        message = DiagnosticArray()
        message.header.stamp = self.node.stamp()
        for servo_id in self.bus.ids:
            reading = statuses[self.bus.ids.index(servo_id)] if statuses is not None else None
            message.status.append(self._status(servo_id, reading))
        self._notes.clear()
        self.publisher.publish(message)

    def _status(self, servo_id: int, reading: ServoStatus | None) -> DiagnosticStatus:
        if reading is None:
            self.read_failures[servo_id] += 1
            findings = [read_failure(servo_id, self.guard.last_error or "bus unavailable")]
        else:
            findings = assess(reading)
        findings += self._notes.get(servo_id, [])
        if self.condition is not None:
            findings.append(self.condition)
        findings.sort(key=lambda finding: -finding.level)
        status = DiagnosticStatus(
            level=bytes([level(findings)]),
            name=f"{self.node.name}: {self.joints[servo_id]}",
            hardware_id=f"{self.bus.port} id {servo_id}",
            message="; ".join(finding.message for finding in findings) or "OK",
        )
        values = {"servo_id": servo_id, "read_failures": self.read_failures[servo_id], **self.counters}
        if reading is not None:
            values.update(
                temperature_c=reading.temperature_c,
                voltage_v=reading.voltage_v,
                load_percent=reading.load_percent,
                position_ticks=reading.position,
                errors=", ".join(reading.errors) or "none",
            )
        status.values = [KeyValue(key=key, value=str(value)) for key, value in values.items()]
        return status
