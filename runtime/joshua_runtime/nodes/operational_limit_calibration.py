"""OPERATIONAL_LIMIT_CALIBRATION: discovers each joint's range while the arm is moved by hand.

Start it with the arm in the middle of its range. As LeRobot does, it switches torque off, clears
each servo's Homing_Offset and position limits, then homes the present pose at tick 2047
(homing_offset = present - 2047). Every 1/rate_hz it reads the positions and widens each joint's
[range_min, range_max]; the limits are published on `topic` as a JointState whose names are
`<joint>.range_min` and `<joint>.range_max` and whose positions are those limits in raw ticks (the
units of the file). `calibration_file` (LeRobot JSON) is rewritten at most every SAVE_INTERVAL_S
while the ranges grow, and once more when the node stops. Servo health goes to /diagnostics.
"""

import time

from sensor_msgs.msg import JointState

from joshua_runtime.drivers.calibration import HALF_TURN_TICKS, MotorCalibration, save_calibration
from joshua_runtime.drivers.sts3215_table import MAX_TICK
from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.servo_bus import BusGuard, bus_from_settings
from joshua_runtime.nodes.servo_diagnostics import ServoDiagnostics

SAVE_INTERVAL_S = 1.0
RANGE_MIN_SUFFIX = ".range_min"
RANGE_MAX_SUFFIX = ".range_max"


class OperationalLimitCalibration(JoshuaNode):
    bus = None

    def start(self) -> None:
        period = settings_checks.period_s(self.settings)
        self.path = self.settings.calibration_file
        if not self.path:
            raise SettingsError("OPERATIONAL_LIMIT_CALIBRATION needs calibration_file")
        self.bus = bus_from_settings(self.settings, use_calibration=False)
        self.bus.open()
        self.offsets = self._home()
        start = self.bus.sync_read("Present_Position")
        self.low = dict(start)
        self.high = dict(start)
        self.dirty = True
        self.next_save = 0.0
        self.guard = BusGuard(self.bus, self.log)
        self.limits = self.publisher(settings_checks.topic(self.settings))
        self.ros.create_timer(period, self._sample)
        self.diagnostics = ServoDiagnostics(self, self.guard)
        self.log.info(f"recording joint ranges into {self.path}: move every joint through its range")

    def _home(self) -> dict[int, int]:
        """Clear offsets and limits, then put the present pose at the middle tick (2047)."""
        bus = self.bus
        bus.disable_torque()
        for servo_id in bus.ids:
            bus.write(servo_id, "Lock", 0)
            bus.write(servo_id, "Homing_Offset", 0)
            bus.write(servo_id, "Min_Position_Limit", 0)
            bus.write(servo_id, "Max_Position_Limit", MAX_TICK)
        offsets = {i: ticks - HALF_TURN_TICKS for i, ticks in bus.sync_read("Present_Position").items()}
        for servo_id, offset in offsets.items():
            bus.write(servo_id, "Homing_Offset", offset)
            bus.write(servo_id, "Lock", 1)
        return offsets

    def _sample(self) -> None:
        positions = self.guard.call(self.bus.sync_read, "Present_Position")
        if positions is None:
            return
        for servo_id, ticks in positions.items():
            if ticks < self.low[servo_id]:
                self.low[servo_id], self.dirty = ticks, True
            if ticks > self.high[servo_id]:
                self.high[servo_id], self.dirty = ticks, True
        self.limits.publish(self._limits_message())
        if self.dirty and time.monotonic() >= self.next_save:
            self._save()

    def _limits_message(self) -> JointState:
        message = JointState()
        message.header.stamp = self.stamp()
        message.header.frame_id = self.settings.frame_id
        names, limits = [], []
        for name, servo_id in zip(self.bus.joint_names, self.bus.ids):
            names += [name + RANGE_MIN_SUFFIX, name + RANGE_MAX_SUFFIX]
            limits += [float(self.low[servo_id]), float(self.high[servo_id])]
        message.name, message.position = names, limits
        return message

    def calibration(self) -> dict[str, MotorCalibration]:
        return {
            name: MotorCalibration(
                id=servo_id,
                drive_mode=0,
                homing_offset=self.offsets[servo_id],
                range_min=self.low[servo_id],
                range_max=self.high[servo_id],
            )
            for name, servo_id in zip(self.bus.joint_names, self.bus.ids)
        }

    def _save(self) -> None:
        save_calibration(self.path, self.calibration())
        self.dirty = False
        self.next_save = time.monotonic() + SAVE_INTERVAL_S

    def close(self) -> None:
        if self.bus is None:
            return
        if getattr(self, "guard", None) is not None:
            self._save()
            unmoved = [n for n, i in zip(self.bus.joint_names, self.bus.ids) if self.low[i] == self.high[i]]
            if unmoved:
                self.log.warning(f"no range recorded for {', '.join(unmoved)}: move them and calibrate again")
        self.bus.close()
