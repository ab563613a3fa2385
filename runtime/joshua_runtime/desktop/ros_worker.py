"""A link to a running robot over ROS 2: joint states in, JointState goals and preset commands out.

Goals go to the command topic as sensor_msgs/JointState (what ACTUATOR_SUBSCRIBER takes). Preset
commands (torque_on, torque_off; the e-stop sends torque_off) go as std_msgs/String to
`<command topic>/preset`, one ActionPacket.preset_commands entry per message. Pose presets (home,
rest, grip_open, user poses) are resolved here and sent as goals, so any actuator follows them.
Telemetry over ROS carries position and effort only: temperature and voltage stay empty.
"""

import math
import time

import rclpy
from PySide6.QtCore import Slot
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_core.servo_topics import preset_topic
from joshua_runtime.desktop.model import (
    PRESET_TORQUE_OFF,
    PRESET_TORQUE_ON,
    JointSample,
    Telemetry,
)
from joshua_runtime.desktop.worker import LinkWorker
from joshua_runtime.ros_node import create_ros_node

ROS_SPIN_HZ = 100.0
QUEUE_DEPTH = 10
EFFORT_TO_PERCENT = 100.0  # JointState effort from the servo nodes is a signed fraction of max torque


class RosWorker(LinkWorker):
    def __init__(self, state_topic: str, command_topic: str, poll_hz: float = ROS_SPIN_HZ):
        super().__init__(poll_hz)
        self.state_topic, self.command_topic = state_topic, command_topic
        self.context = None
        self.node = None
        self.executor = None
        self._latest: JointState | None = None

    def connect_link(self) -> bool:
        try:
            self.context = rclpy.Context()
            rclpy.init(context=self.context)
            self.node = create_ros_node("joshua_desktop", context=self.context)
        except RuntimeError as exc:  # rclpy's RCLError: a broken ROS environment
            self.failed.emit(f"cannot start ROS: {' '.join(str(exc).split())}")
            return False
        # Best effort takes both reliable and best-effort publishers; commands go reliable.
        listen = QoSProfile(depth=QUEUE_DEPTH, reliability=ReliabilityPolicy.BEST_EFFORT)
        self.node.create_subscription(JointState, self.state_topic, self._receive, listen)
        self.goals = self.node.create_publisher(JointState, self.command_topic, QUEUE_DEPTH)
        self.presets = self.node.create_publisher(String, preset_topic(self.command_topic), QUEUE_DEPTH)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.connected.emit(f"ROS {self.state_topic} -> {self.command_topic}")
        return True

    def disconnect_link(self) -> None:
        if self.context is None:
            return
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)
        self.context = None

    def poll(self) -> None:
        self.executor.spin_once(timeout_sec=0)
        message, self._latest = self._latest, None
        if message is None:
            return
        efforts = list(message.effort) or [0.0] * len(message.name)
        joints = {
            name: JointSample(position=position, load_percent=effort * EFFORT_TO_PERCENT)
            for name, position, effort in zip(message.name, message.position, efforts)
        }
        self.telemetry.emit(Telemetry(time.monotonic(), joints))

    def _receive(self, message: JointState) -> None:
        self._latest = message

    @Slot(object)
    def send_goals(self, goals: dict) -> None:
        named = {name: value for name, value in goals.items() if not math.isnan(value)}
        if named:
            self.goals.publish(JointState(name=list(named), position=list(named.values())))

    def _preset(self, command: str) -> None:
        self.presets.publish(String(data=command))

    @Slot(bool)
    def set_torque(self, on: bool) -> None:
        self._preset(PRESET_TORQUE_ON if on else PRESET_TORQUE_OFF)

    @Slot()
    def estop(self) -> None:
        self._preset(PRESET_TORQUE_OFF)
        self.message.emit(f"E-STOP: torque_off sent on {preset_topic(self.command_topic)}")

    @Slot(str, bool)
    def set_joint_torque(self, joint: str, on: bool) -> None:
        self.failed.emit("torque per joint needs a direct serial connection to the bus")

    @Slot(str, object)
    def calibrate(self, step: str, argument) -> None:
        self.failed.emit("calibration needs a direct serial connection to the bus")
