"""Following action chunks (trajectory_msgs/msg/JointTrajectory) at an actuator's own control rate.

The one rule of ACTUATOR_SUBSCRIBER, MOCK_ACTUATOR_SUBSCRIBER and the simulation's actuators (the C++
actuator mirrors it in cpp/nodes/trajectory_follower.cpp; tests/cpp checks they agree):

- A chunk's points lie at `header.stamp + time_from_start` on the ROS clock; a zero stamp means the
  moment the chunk arrives (as ros2_control's joint_trajectory_controller reads it).
- A chunk replaces whatever is left of the one in force. Its points that are already in the past are
  dropped: the goal moves linearly from the goal in force at arrival (for the first chunk, the chunk's
  own value at that moment) to the first point still ahead, then linearly from point to point. A chunk whose points all lie in the past, or stamped earlier than
  the one in force, changes nothing (it is reported as dropped).
- Every control period (1/rate_hz) the actuator sends the goal of that moment.
- Once the last point's time has passed, the last point is held and the chunk is over: a node with a
  command timeout (command_timeout_s) counts its silence from then and applies on_command_timeout.
- Joints are matched by name; a joint the chunk does not name keeps its goal (NaN: left alone). A
  chunk without joint names is taken in joint order when its width matches.
"""

from dataclasses import dataclass

import numpy as np

from joshua_core.message_types import JOINT_TRAJECTORY

NANOSECONDS_PER_SECOND = 1_000_000_000
DROP_LOG_PERIOD_S = 2.0  # at most one "action chunk dropped" line per this many seconds


@dataclass(frozen=True)
class Chunk:
    """Timed goals in the follower's joint order: times_s (ROS clock, increasing), positions (points x joints)."""

    stamp_s: float
    times_s: np.ndarray
    positions: np.ndarray


class ChunkRejected(ValueError):
    """A trajectory message that cannot be followed (its points are inconsistent)."""


def is_trajectory(topic) -> bool:
    """Whether a command topic of the settings carries action chunks."""
    return topic.message_type == JOINT_TRAJECTORY


def ros_seconds(time_message) -> float:
    """A builtin_interfaces Time or Duration in seconds."""
    return time_message.sec + time_message.nanosec / NANOSECONDS_PER_SECOND


def now_s(ros_node) -> float:
    """The node's ROS clock in seconds (the clock chunk stamps are on)."""
    return ros_node.get_clock().now().nanoseconds / NANOSECONDS_PER_SECOND


def chunk_from_trajectory(message, joint_names: list[str], arrival_s: float) -> Chunk:
    """The Chunk of a JointTrajectory in `joint_names` order; ChunkRejected when it cannot be followed."""
    width = len(joint_names)
    names = list(message.joint_names)
    if names:
        index = {name: i for i, name in enumerate(joint_names)}
        columns = [(column, index[name]) for column, name in enumerate(names) if name in index]
    elif message.points and len(message.points[0].positions) == width:
        names, columns = list(joint_names), [(i, i) for i in range(width)]
    else:
        raise ChunkRejected(f"the trajectory names no joints and its points do not have {width} positions")
    if not message.points:
        raise ChunkRejected("the trajectory has no points")
    positions = np.full((len(message.points), width), np.nan)
    offsets = np.empty(len(message.points))
    for row, point in enumerate(message.points):
        if len(point.positions) != len(names):
            raise ChunkRejected(f"point {row} has {len(point.positions)} positions for {len(names)} joints")
        for column, joint in columns:
            positions[row, joint] = point.positions[column]
        offsets[row] = ros_seconds(point.time_from_start)
    if np.any(np.diff(offsets) <= 0):
        raise ChunkRejected("time_from_start does not increase from point to point")
    stamp = ros_seconds(message.header.stamp) or arrival_s
    return Chunk(stamp_s=stamp, times_s=stamp + offsets, positions=positions)


class TrajectoryFollower:
    """The goal of every joint at any moment, from the chunks received so far (see the module's rule)."""

    def __init__(self, joint_count: int):
        self.joint_count = joint_count
        self._times = np.empty(0)
        self._positions = np.empty((0, joint_count))
        self._stamp_s = -np.inf
        self.accepted = 0
        self.dropped = 0

    def accept(self, chunk: Chunk, now_s: float) -> str:
        """Take a chunk received at `now_s`; "" when it is followed, else why it was dropped."""
        if chunk.stamp_s < self._stamp_s:
            self.dropped += 1
            return f"stamped {self._stamp_s - chunk.stamp_s:.3f} s before the chunk in force"
        ahead = chunk.times_s > now_s
        if not ahead.any():
            self.dropped += 1
            return f"its last point was {now_s - chunk.times_s[-1]:.3f} s in the past on arrival"
        own = _sample(chunk.times_s, chunk.positions, now_s)
        current = self.goal(now_s)
        start = own if current is None else np.where(np.isnan(current), own, current)
        times = np.concatenate(([now_s], chunk.times_s[ahead]))
        positions = np.vstack((start, chunk.positions[ahead]))
        self._times, self._positions, self._stamp_s = times, positions, chunk.stamp_s
        self.accepted += 1
        return ""

    def goal(self, now_s: float) -> np.ndarray | None:
        """The goal at `now_s` (NaN: leave the joint alone); None before the first chunk."""
        return _sample(self._times, self._positions, now_s) if self._times.size else None

    def executing(self, now_s: float) -> bool:
        """Whether a chunk is in force at `now_s` (received and its last point not yet passed)."""
        return bool(self._times.size) and now_s <= self._times[-1]

    def end_s(self) -> float | None:
        """When the chunk in force ends (its last point), None before the first chunk."""
        return float(self._times[-1]) if self._times.size else None


def _sample(times: np.ndarray, positions: np.ndarray, at_s: float) -> np.ndarray:
    """Positions at `at_s`, linear between points, the first before them and the last after them."""
    if at_s <= times[0]:
        return positions[0].copy()
    if at_s >= times[-1]:
        return positions[-1].copy()
    after = int(np.searchsorted(times, at_s, side="right"))
    weight = (at_s - times[after - 1]) / (times[after] - times[after - 1])
    return positions[after - 1] + weight * (positions[after] - positions[after - 1])


class ChunkCommands:
    """A node's command topic taken as action chunks: `drive(goals)` every control period while one is in force.

    `goals` are in `joint_names` order (NaN: leave alone). After a chunk's last point has passed, that
    point is driven once more, exactly, and nothing after it until the next chunk: the actuator holds it.
    """

    def __init__(self, node, topic, joint_names: list[str], period_s: float, drive):
        self.node, self.joint_names, self.drive = node, list(joint_names), drive
        self.follower = TrajectoryFollower(len(self.joint_names))
        self.driven = 0  # goals sent from chunks in force
        self._holding = True
        self.subscription = node.subscription(topic, self.receive)
        self.timer = node.ros.create_timer(period_s, self.tick)

    def receive(self, message) -> None:
        arrival = now_s(self.node.ros)
        try:
            dropped = self.follower.accept(chunk_from_trajectory(message, self.joint_names, arrival), arrival)
        except ChunkRejected as exc:
            dropped = str(exc)
        if dropped:
            self.node.log.warning(f"action chunk dropped: {dropped}", throttle_duration_sec=DROP_LOG_PERIOD_S)

    def tick(self) -> None:
        now = now_s(self.node.ros)
        if self.follower.executing(now):
            self._holding = False
            self.driven += 1
            self.drive(self.follower.goal(now))
        elif not self._holding:
            self._holding = True
            self.drive(self.follower.goal(now))
