"""Watches the simulated SO-100 over ROS for `make demo-train`: commands received, grasp point against the goal."""

import time

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.train.demonstrations import DEMONSTRATION_GOAL

QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


class ArmWatch:
    """Counts the policy's commands and measures the grasp point's distance to DEMONSTRATION_GOAL."""

    def __init__(self, state_topic: str, command_topic: str):
        self.kinematics = arm.ArmKinematics()
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("demo_train_watch", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.commands = 0
        self.first_command_at: float | None = None  # time.monotonic() of the first command
        self.latest_m = self.start_m = None
        self.node.create_subscription(JointState, state_topic, self._state, QOS)
        self.node.create_subscription(JointState, command_topic, self._command, QOS)

    def __enter__(self) -> "ArmWatch":
        return self

    def __exit__(self, *exc_info) -> None:
        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def _state(self, message: JointState) -> None:
        by_name = dict(zip(message.name, message.position))
        if all(joint in by_name for joint in arm.ARM_JOINTS):
            point = self.kinematics.grasp_point([by_name[joint] for joint in arm.ARM_JOINTS])
            self.latest_m = float(np.linalg.norm(point - DEMONSTRATION_GOAL))

    def _command(self, _message: JointState) -> None:
        if self.commands == 0:
            self.start_m = self.latest_m
            self.first_command_at = time.monotonic()
        self.commands += 1

    def spin(self, seconds: float) -> None:
        self.executor.spin_once(timeout_sec=seconds)

    def summary(self) -> dict:
        return {"commands": self.commands, "start_m": self.start_m, "end_m": self.latest_m}
