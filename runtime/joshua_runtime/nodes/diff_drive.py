"""ROS side of every differential-drive base (real, mock, simulated): Twist in; Odometry and wheel states out.

A base supplies its wheels (`WheelDrive`); `BaseTopics` turns each Twist into wheel speeds (limited
together to the motors' top speed, so the path keeps its curvature), stops the wheels when no Twist
came for command_timeout_s, and at rate_hz integrates the newest wheel angles into nav_msgs/msg/Odometry on
odom_topic (frame_id -> child frame base_link), the same pose as a transform on /tf, and a JointState
of the wheels on state_topic.
"""

import time

from nav_msgs.msg import Odometry as OdometryMessage
from sensor_msgs.msg import JointState

from joshua_core.settings import NodeSettings
from joshua_runtime.convert.transforms import TF_QOS, TF_TOPIC, odometry_transform
from joshua_runtime.errors import SettingsError
from joshua_runtime.nodes import settings_checks
from joshua_runtime.odometry import Geometry, Odometry, limit_speeds, yaw_quaternion

# A LEGO motor's top speed (about 1000 deg/s).
MAX_WHEEL_SPEED_RAD_S = 17.45
CHILD_FRAME_ID = "base_link"


class WheelDrive:
    """The two wheels of a base."""

    def set_wheel_speeds(self, left_rad_s: float, right_rad_s: float) -> None:
        raise NotImplementedError

    def wheel_angles(self) -> tuple[float, float, float] | None:
        """(left rad, right rad, time s) of the newest reading; None while there is none."""
        raise NotImplementedError


def geometry(settings: NodeSettings) -> Geometry:
    """The base's wheel geometry; both lengths must be positive."""
    if not settings.wheel_radius_m > 0 or not settings.track_width_m > 0:
        raise SettingsError(
            f"wheel_radius_m and track_width_m must be positive, got "
            f"{settings.wheel_radius_m!r} and {settings.track_width_m!r}"
        )
    return Geometry(settings.wheel_radius_m, settings.track_width_m)


def wheel_names(settings: NodeSettings) -> list[str]:
    names = list(settings.joint_names)
    if len(names) != 2:
        raise SettingsError(f"a differential-drive base has 2 wheel joint_names, got {len(names)}")
    return names


class BaseTopics:
    """Subscribes the base's Twist, publishes its odometry and wheel states, enforces the command timeout."""

    def __init__(self, node, settings: NodeSettings, wheels: WheelDrive):
        self.node, self.wheels = node, wheels
        self.geometry = geometry(settings)
        self.odometry = Odometry(self.geometry)
        self.names = wheel_names(settings)
        if not settings.command_timeout_s > 0:
            raise SettingsError(f"command_timeout_s must be positive, got {settings.command_timeout_s!r}")
        self.timeout_s = settings.command_timeout_s
        self.frame_id = settings.frame_id
        self.last_command: float | None = None
        self.previous: tuple[float, float, float] | None = None
        self.velocities = (0.0, 0.0)
        self.odom_publisher = node.publisher(settings_checks.topic(settings, "odom_topic"))
        from tf2_msgs.msg import TFMessage

        self.tf_message = TFMessage
        self.tf_publisher = node.ros.create_publisher(TFMessage, TF_TOPIC, TF_QOS)
        self.state_publisher = node.publisher(settings.state_topic) if settings.HasField("state_topic") else None
        self.subscription = node.subscription(settings_checks.topic(settings), self.on_twist)
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.tick)

    def on_twist(self, msg) -> None:
        left, right = self.geometry.wheel_speeds(msg.linear.x, msg.angular.z)
        self.wheels.set_wheel_speeds(*limit_speeds(left, right, MAX_WHEEL_SPEED_RAD_S))
        self.last_command = time.monotonic()

    def wheels_lost(self) -> None:
        """The wheels' link dropped: forget the last Twist, and restart odometry from the next reading."""
        self.last_command = None
        self.previous = None
        self.velocities = (0.0, 0.0)
        self.odometry.rebase()

    def tick(self) -> None:
        if self.last_command is not None and time.monotonic() - self.last_command > self.timeout_s:
            self.wheels.set_wheel_speeds(0.0, 0.0)
            self.last_command = None
            self.node.log.info(f"no Twist for {self.timeout_s:g} s: wheels stopped")
        reading = self.wheels.wheel_angles()
        if reading is None:
            return
        if reading != self.previous:  # a new reading; else the last pose is published again, at rate_hz
            if self.previous is not None and reading[2] > self.previous[2]:
                dt = reading[2] - self.previous[2]
                self.velocities = ((reading[0] - self.previous[0]) / dt, (reading[1] - self.previous[1]) / dt)
            self.previous = reading
            self.odometry.update(*reading)
        stamp = self.node.stamp()
        odometry = self.odometry_message(self.odometry.pose, stamp)
        self.odom_publisher.publish(odometry)
        self.tf_publisher.publish(self.tf_message(transforms=[odometry_transform(odometry)]))
        if self.state_publisher is not None:
            state = JointState(name=self.names, position=[reading[0], reading[1]], velocity=list(self.velocities))
            state.header.stamp, state.header.frame_id = stamp, CHILD_FRAME_ID
            self.state_publisher.publish(state)

    def odometry_message(self, pose, stamp) -> OdometryMessage:
        msg = OdometryMessage()
        msg.header.stamp, msg.header.frame_id, msg.child_frame_id = stamp, self.frame_id, CHILD_FRAME_ID
        msg.pose.pose.position.x, msg.pose.pose.position.y = pose.x, pose.y
        q = msg.pose.pose.orientation
        q.x, q.y, q.z, q.w = yaw_quaternion(pose.yaw)
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = pose.linear, pose.angular
        return msg
