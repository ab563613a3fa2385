"""A guided, per-joint calibration of one arm, producing LeRobot calibration JSON.

For each joint in turn: the user holds that joint at its homing pose (a pose one joint can always
reach, described per robot, rather than "the middle of the range" of every joint at once) and the
engine writes Homing_Offset so that pose reads tick 2047; then the user sweeps the joint between its
end stops while MIN/POS/MAX update live. A continuous joint (wrist_roll) is homed the same way but
keeps the full 0..4095 range, so its zero is exactly its homing pose on every arm: a leader and a
follower homed at the same pose agree. A sweep that steps from one end of the encoder to the other
between two samples crossed the wrap point and is refused.

The engine does bus I/O only when called; a terminal command and the desktop app drive it.
"""

from dataclasses import dataclass, field

from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.drivers.calibration import HALF_TURN_TICKS, MotorCalibration
from joshua_runtime.drivers.sts3215_table import BY_NAME, MAX_TICK, TICKS_PER_TURN
from joshua_runtime.errors import JoshuaError

MAX_HOMING_OFFSET = (1 << BY_NAME["Homing_Offset"].sign_bit) - 1
WRAP_EDGE_TICKS = TICKS_PER_TURN // 8  # a step from this close to one end of the encoder to the other is a wrap
MIN_SWEEP_TICKS = 20  # a "sweep" shorter than this was not a sweep

SO100_HOMING_POSES = {
    "shoulder_pan": "arm pointing straight ahead over the front of the base",
    "shoulder_lift": "upper arm straight up",
    "elbow_flex": "forearm at a right angle to the upper arm",
    "wrist_flex": "hand in line with the forearm",
    "wrist_roll": "jaws vertical, fixed jaw on top",
    "gripper": "jaws closed",
}


@dataclass(frozen=True)
class ArmModel:
    """What the calibration needs to know about a robot arm."""

    joints: tuple[str, ...]
    ids: tuple[int, ...]
    homing_poses: dict[str, str]
    continuous_joints: frozenset[str]

    def homing_instruction(self, joint: str) -> str:
        return f"Hold {joint} at its homing pose: {self.homing_poses[joint]}."

    def sweep_instruction(self, joint: str) -> str:
        if joint in self.continuous_joints:
            return f"{joint} turns freely: its range is the full turn, no sweep needed."
        return f"Move {joint} slowly from one end stop to the other."


ARMS = {
    name: ArmModel(tuple(SO100_JOINTS), tuple(range(1, 7)), SO100_HOMING_POSES, frozenset({"wrist_roll"}))
    for name in ("so100", "so101")
}


class CalibrationError(JoshuaError):
    """The recorded calibration is unusable (no sweep, a wrap, a joint left out)."""


@dataclass
class JointRange:
    """Live MIN/POS/MAX of one joint during its sweep, in the homed frame."""

    position: int
    low: int
    high: int
    wrapped: bool = False

    def update(self, position: int) -> None:
        low_edge, high_edge = WRAP_EDGE_TICKS, MAX_TICK - WRAP_EDGE_TICKS
        if min(self.position, position) < low_edge and max(self.position, position) > high_edge:
            self.wrapped = True
        self.position = position
        self.low, self.high = min(self.low, position), max(self.high, position)


@dataclass
class CalibrationFlow:
    """Per-joint homing and sweeping on an open bus; `result()` gives the calibration to save."""

    bus: object
    arm: ArmModel
    offsets: dict[str, int] = field(default_factory=dict)
    ranges: dict[str, JointRange] = field(default_factory=dict)

    def id_of(self, joint: str) -> int:
        return self.arm.ids[self.arm.joints.index(joint)]

    def start(self, joints: tuple[str, ...] | None = None) -> None:
        """Torque off; position mode, offsets and limits cleared on `joints` (default all; unlocked until
        finish() or store())."""
        bus = self.bus
        bus.disable_torque(list(self.arm.ids))
        for servo_id in (self.id_of(joint) for joint in joints or self.arm.joints):
            bus.write(servo_id, "Lock", 0)
            bus.write(servo_id, "Operating_Mode", 0)
            bus.write(servo_id, "Homing_Offset", 0)
            bus.write(servo_id, "Min_Position_Limit", 0)
            bus.write(servo_id, "Max_Position_Limit", MAX_TICK)

    def home(self, joint: str) -> int:
        """Make the present pose of `joint` read 2047; returns the Homing_Offset written."""
        servo_id = self.id_of(joint)
        self.bus.write(servo_id, "Homing_Offset", 0)
        raw = self.bus.read(servo_id, "Present_Position")
        offset = max(-MAX_HOMING_OFFSET, min(MAX_HOMING_OFFSET, raw - HALF_TURN_TICKS))
        self.bus.write(servo_id, "Homing_Offset", offset)
        self.offsets[joint] = offset
        position = self.bus.read(servo_id, "Present_Position")
        self.ranges[joint] = JointRange(position, position, position)
        return offset

    def sample(self, joint: str) -> JointRange:
        """Read `joint` once and widen its range."""
        position = self.bus.read(self.id_of(joint), "Present_Position")
        self.ranges[joint].update(position)
        return self.ranges[joint]

    def calibration_of(self, joint: str) -> MotorCalibration:
        if joint not in self.offsets:
            raise CalibrationError(f"{joint} was never homed")
        recorded = self.ranges[joint]
        if joint in self.arm.continuous_joints:
            low, high = 0, MAX_TICK
        elif recorded.wrapped:
            raise CalibrationError(
                f"{joint} crossed the encoder's wrap point while sweeping: home it nearer the middle of its travel"
            )
        elif recorded.high == recorded.low:
            raise CalibrationError(f"{joint} did not move during its sweep")
        elif recorded.high - recorded.low < MIN_SWEEP_TICKS:
            raise CalibrationError(f"{joint} moved only {recorded.high - recorded.low} ticks: sweep it end to end")
        else:
            low, high = recorded.low, recorded.high
        return MotorCalibration(self.id_of(joint), 0, self.offsets[joint], low, high)

    def result(self) -> dict[str, MotorCalibration]:
        return {joint: self.calibration_of(joint) for joint in self.arm.joints}

    def store(self, motors: dict[str, MotorCalibration]) -> None:
        """Store the limits of these checked joints in their servos and lock their EEPROM."""
        for motor in motors.values():
            self.bus.write(motor.id, "Min_Position_Limit", motor.range_min)
            self.bus.write(motor.id, "Max_Position_Limit", motor.range_max)
            self.bus.write(motor.id, "Lock", 1)

    def finish(self) -> dict[str, MotorCalibration]:
        """Check every joint, store the limits in the servos and lock their EEPROM."""
        motors = self.result()
        self.store(motors)
        return motors
