"""A link straight to an STS3215 bus: telemetry by SYNC_READ, goals by SYNC_WRITE, calibration on the bus."""

import math
import time

from PySide6.QtCore import Slot

from joshua_runtime.desktop.model import JointSample, Telemetry
from joshua_runtime.desktop.worker import LinkWorker
from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.calibration import calibration_for_bus, save_calibration
from joshua_runtime.drivers.sts3215 import Sts3215Driver
from joshua_runtime.drivers.sts3215_health import assess, level
from joshua_runtime.drivers.sts3215_status import read_status
from joshua_runtime.drivers.sts3215_table import encode_value, register
from joshua_runtime.errors import JoshuaError
from joshua_runtime.servo_tools.bus import TOOL_REPLY_TIMEOUT_S, TOOL_RETRIES
from joshua_runtime.servo_tools.calibration_flow import ARMS, CalibrationFlow

SERIAL_POLL_HZ = 50.0


class SerialWorker(LinkWorker):
    direct_bus = True

    def __init__(
        self,
        port: str,
        joints: list[str],
        ids: list[int],
        baud_rate: int,
        calibration_file: str | None = None,
        poll_hz: float = SERIAL_POLL_HZ,
        arm: str = "so100",
    ):
        super().__init__(poll_hz)
        self.port, self.joints, self.ids, self.baud_rate = port, list(joints), list(ids), baud_rate
        self.calibration_file = calibration_file
        self.arm = ARMS[arm]
        self.bus: Sts3215Driver | None = None
        self.torque: dict[int, bool] = {}
        self.flow: CalibrationFlow | None = None
        self.sweeping: str | None = None
        self._failing = False

    # --- link ---------------------------------------------------------------------------------
    def connect_link(self) -> bool:
        try:
            calibration = calibration_for_bus(self.calibration_file, self.joints, self.ids)
            self.bus = Sts3215Driver(
                self.port,
                self.ids,
                self.joints,
                baud_rate=self.baud_rate,
                calibration=calibration if self.calibration_file else None,
                reply_timeout_s=TOOL_REPLY_TIMEOUT_S,
                max_retries=TOOL_RETRIES,
            )
            self.bus.open()
            self.torque = self.bus.torque_enabled()
        except JoshuaError as exc:
            self.failed.emit(str(exc))
            return False
        calibrated = f", calibration {self.calibration_file}" if self.calibration_file else ", uncalibrated"
        self.connected.emit(f"serial {self.port} @ {self.baud_rate} baud, {len(self.ids)} servos{calibrated}")
        return True

    def disconnect_link(self) -> None:
        if self.bus is not None:
            self.bus.close()

    def poll(self) -> None:
        try:
            statuses = read_status(self.bus, self.ids)
            if self.sweeping:
                self.calibration.emit(("range", self.sweeping, self.flow.sample(self.sweeping)))
        except JoshuaError as exc:
            if not self._failing:
                self.failed.emit(str(exc))
            self._failing = True
            return
        if self._failing:
            self.message.emit("bus answering again")
            self._failing = False
        joints = {}
        for name, motor, status in zip(self.joints, self.bus.calibration, statuses):
            joints[name] = JointSample(
                position=motor.to_radians(status.position),
                load_percent=status.load_percent,
                temperature_c=status.temperature_c,
                voltage_v=status.voltage_v,
                torque_on=self.torque.get(status.id),
                errors=tuple(status.errors),
                health=level(findings := assess(status)),
                findings=tuple(f.message for f in findings),
            )
        self.telemetry.emit(Telemetry(time.monotonic(), joints))

    # --- commands -----------------------------------------------------------------------------
    def _command(self, action, *args) -> None:
        try:
            action(*args)
        except (JoshuaError, ValueError) as exc:
            self.failed.emit(str(exc))

    @Slot(object)
    def send_goals(self, goals: dict) -> None:
        index = {name: i for i, name in enumerate(self.joints)}
        raw = {
            self.ids[index[name]]: self.bus.calibration[index[name]].to_ticks(value)
            for name, value in goals.items()
            if name in index and not math.isnan(value)
        }
        self._command(self.bus.sync_write, "Goal_Position", raw)

    @Slot(bool)
    def set_torque(self, on: bool) -> None:
        self._command(self.bus.enable_torque if on else self.bus.disable_torque)
        self.torque = dict.fromkeys(self.ids, on)

    @Slot(str, bool)
    def set_joint_torque(self, joint: str, on: bool) -> None:
        servo_id = self.ids[self.joints.index(joint)]
        self._command(self.bus.enable_torque if on else self.bus.disable_torque, [servo_id])
        self.torque[servo_id] = on

    @Slot()
    def estop(self) -> None:
        """Torque off on every servo of the bus, listed or not: a broadcast WRITE, then a SYNC_WRITE."""
        reg = register("Torque_Enable")
        packet = proto.encode(proto.BROADCAST_ID, proto.INST_WRITE, bytes([reg.address]) + encode_value(reg, 0))
        self._command(self.bus.transport.send, packet)
        self._command(self.bus.disable_torque)
        self.torque = dict.fromkeys(self.ids, False)
        self.message.emit("E-STOP: torque off on every servo")

    @Slot(str, object)
    def calibrate(self, step: str, argument) -> None:
        """Steps: start; home <joint>; sweep <joint>; finish <path>; cancel."""
        try:
            if step == "start":
                self.flow = CalibrationFlow(self.bus, self.arm)
                self.flow.start()
                self.torque = dict.fromkeys(self.ids, False)
                self.calibration.emit(("started", None, None))
            elif step == "home":
                self.sweeping = None
                offset = self.flow.home(argument)
                self.calibration.emit(("homed", argument, (offset, self.flow.ranges[argument])))
                if argument not in self.arm.continuous_joints:
                    self.sweeping = argument
            elif step == "finish":
                self.sweeping = None
                motors = self.flow.finish()
                save_calibration(argument, motors)
                self.bus.calibration = [motors[name] for name in self.joints]
                self.calibration_file = str(argument)
                self.calibration.emit(("saved", str(argument), motors))
            elif step == "cancel":
                self.sweeping, self.flow = None, None
        except JoshuaError as exc:
            self.failed.emit(str(exc))
