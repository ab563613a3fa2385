"""Differential-drive kinematics and odometry, pure: wheel speeds from a body velocity, pose from wheel angles.

Units: metres, radians, seconds. x forward, y left, yaw counter-clockwise; a positive wheel angle
rolls that wheel forward. Between two readings the base is taken to move on a circular arc (exact
for constant wheel speeds), so a fast reading rate is not needed for accuracy on smooth paths.
"""

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Geometry:
    wheel_radius_m: float
    track_width_m: float

    def wheel_speeds(self, linear_m_s: float, angular_rad_s: float) -> tuple[float, float]:
        """(left, right) wheel speeds in rad/s for a body velocity."""
        half = angular_rad_s * self.track_width_m / 2
        return (linear_m_s - half) / self.wheel_radius_m, (linear_m_s + half) / self.wheel_radius_m

    def body_velocity(self, left_rad_s: float, right_rad_s: float) -> tuple[float, float]:
        """(linear m/s, angular rad/s) of the body for wheel speeds."""
        left, right = left_rad_s * self.wheel_radius_m, right_rad_s * self.wheel_radius_m
        return (left + right) / 2, (right - left) / self.track_width_m


def limit_speeds(left: float, right: float, max_speed: float) -> tuple[float, float]:
    """Scale both wheel speeds down together so neither exceeds max_speed: the path's curvature is kept."""
    fastest = max(abs(left), abs(right))
    if fastest <= max_speed or fastest == 0:
        return left, right
    scale = max_speed / fastest
    return left * scale, right * scale


@dataclass
class Pose:
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    linear: float = 0.0  # m/s
    angular: float = 0.0  # rad/s


class Odometry:
    """Integrates wheel angles (rad) read at times (s) into a pose and a body velocity."""

    def __init__(self, geometry: Geometry):
        self.geometry = geometry
        self.pose = Pose()
        self._last: tuple[float, float, float] | None = None

    def rebase(self) -> None:
        """Keep the pose, stand still, and take the next reading as the new reference.

        For wheel angles that start over (a hub that restarted while the link was down).
        """
        self._last = None
        self.pose.linear = self.pose.angular = 0.0

    def update(self, left_rad: float, right_rad: float, time_s: float) -> Pose:
        if self._last is None:
            self._last = (left_rad, right_rad, time_s)
            return self.pose
        last_left, last_right, last_time = self._last
        self._last = (left_rad, right_rad, time_s)
        distance, turn = self.geometry.body_velocity(left_rad - last_left, right_rad - last_right)
        pose = self.pose
        if abs(turn) < 1e-9:
            pose.x += distance * math.cos(pose.yaw)
            pose.y += distance * math.sin(pose.yaw)
        else:
            radius = distance / turn
            pose.x += radius * (math.sin(pose.yaw + turn) - math.sin(pose.yaw))
            pose.y -= radius * (math.cos(pose.yaw + turn) - math.cos(pose.yaw))
        pose.yaw = math.atan2(math.sin(pose.yaw + turn), math.cos(pose.yaw + turn))
        dt = time_s - last_time
        if dt > 0:
            pose.linear, pose.angular = distance / dt, turn / dt
        return pose


def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by yaw about z."""
    return 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)
