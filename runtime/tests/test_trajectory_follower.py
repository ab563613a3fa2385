"""The action-chunk rule every actuator follows: timed points, linear goals, newer chunks, the end of a chunk."""

import math

import numpy as np
import pytest
from builtin_interfaces.msg import Duration, Time
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from joshua_runtime.nodes.trajectory_follower import ChunkRejected, TrajectoryFollower, chunk_from_trajectory

JOINTS = ["shoulder_pan", "gripper"]
STEP_S = 0.1


def trajectory(stamp_s: float, rows, names=JOINTS, step_s: float = STEP_S) -> JointTrajectory:
    message = JointTrajectory()
    message.header.stamp = Time(sec=int(stamp_s), nanosec=round((stamp_s % 1) * 1e9))
    message.joint_names = list(names)
    for i, row in enumerate(rows):
        offset = i * step_s
        message.points.append(
            JointTrajectoryPoint(
                positions=[float(v) for v in row],
                time_from_start=Duration(sec=int(offset), nanosec=round((offset % 1) * 1e9)),
            )
        )
    return message


def follower_with(message, now_s: float) -> TrajectoryFollower:
    follower = TrajectoryFollower(len(JOINTS))
    assert follower.accept(chunk_from_trajectory(message, JOINTS, now_s), now_s) == ""
    return follower


def test_goals_are_linear_between_points_and_the_last_point_is_held():
    follower = follower_with(trajectory(100.0, [[0, 0], [1, 10], [3, 10]]), now_s=99.9)
    assert follower.goal(100.05) == pytest.approx([0.5, 5.0])
    assert follower.goal(100.15) == pytest.approx([2.0, 10.0])
    assert follower.executing(100.2)
    assert follower.goal(100.2) == pytest.approx([3.0, 10.0])
    assert not follower.executing(100.21)
    assert follower.goal(105.0) == pytest.approx([3.0, 10.0])
    assert follower.end_s() == pytest.approx(100.2)


def test_points_in_the_past_are_dropped_and_the_goal_moves_on_from_where_it_was():
    follower = TrajectoryFollower(len(JOINTS))
    assert follower.goal(0.0) is None
    first = trajectory(10.0, [[0, 0], [1, 1], [2, 2], [3, 3]])
    assert follower.accept(chunk_from_trajectory(first, JOINTS, 10.0), 10.0) == ""
    at_arrival = follower.goal(10.15)
    assert at_arrival == pytest.approx([1.5, 1.5])
    # Stamped at 10.05 and arriving at 10.15: the points at 10.05 and 10.15 are past, 10.25 is next.
    newer = trajectory(10.05, [[9, 9], [9, 9], [5, -5], [6, -6]])
    assert follower.accept(chunk_from_trajectory(newer, JOINTS, 10.15), 10.15) == ""
    assert follower.goal(10.15) == pytest.approx(at_arrival)
    assert follower.goal(10.20) == pytest.approx([3.25, -1.75])
    assert follower.goal(10.25) == pytest.approx([5.0, -5.0])
    assert follower.goal(10.30) == pytest.approx([5.5, -5.5])
    assert follower.end_s() == pytest.approx(10.35)


def test_late_and_out_of_order_chunks_change_nothing():
    follower = follower_with(trajectory(20.0, [[1, 1], [2, 2]]), now_s=20.0)
    before = follower.goal(20.05)
    older = chunk_from_trajectory(trajectory(19.9, [[7, 7], [8, 8], [9, 9]]), JOINTS, 20.05)
    assert "before the chunk in force" in follower.accept(older, 20.05)
    late = chunk_from_trajectory(trajectory(20.01, [[7, 7], [8, 8]]), JOINTS, 20.5)
    assert "in the past on arrival" in follower.accept(late, 20.5)
    assert follower.goal(20.05) == pytest.approx(before)
    assert (follower.accepted, follower.dropped) == (1, 2)


def test_joints_are_matched_by_name_and_unnamed_ones_are_left_alone():
    follower = follower_with(trajectory(5.0, [[0.5], [0.7]], names=["gripper"]), now_s=5.0)
    goal = follower.goal(5.05)
    assert math.isnan(goal[0]) and goal[1] == pytest.approx(0.6)
    ordered = chunk_from_trajectory(trajectory(5.0, [[1, 2]], names=[]), JOINTS, 5.0)
    assert ordered.positions.tolist() == [[1.0, 2.0]]
    foreign = chunk_from_trajectory(trajectory(5.0, [[1, 2]], names=["elbow", "gripper"]), JOINTS, 5.0)
    assert math.isnan(foreign.positions[0, 0]) and foreign.positions[0, 1] == 2.0


def test_a_zero_stamp_starts_on_arrival():
    chunk = chunk_from_trajectory(trajectory(0.0, [[0, 0], [1, 1]]), JOINTS, 42.0)
    assert chunk.stamp_s == 42.0 and chunk.times_s.tolist() == pytest.approx([42.0, 42.1])


@pytest.mark.parametrize(
    ("message", "reason"),
    [
        (trajectory(1.0, []), "no points"),
        (trajectory(1.0, [[1, 2, 3]], names=[]), "names no joints"),
        (trajectory(1.0, [[1, 2], [1]]), "point 1 has 1 positions for 2 joints"),
        (trajectory(1.0, [[1, 2], [3, 4]], step_s=0.0), "does not increase"),
    ],
)
def test_inconsistent_trajectories_are_rejected_with_the_reason(message, reason):
    with pytest.raises(ChunkRejected, match=reason):
        chunk_from_trajectory(message, JOINTS, 1.0)


def test_a_goal_is_sampled_every_control_period_from_a_chunk_longer_than_one_model_call():
    """At 100 Hz a 20-point chunk at 30 Hz yields a goal every period for its whole length."""
    rows = np.linspace([0, 0], [1, 1], 20)
    follower = follower_with(trajectory(1.0, rows, step_s=1 / 30), now_s=1.0)
    ticks = np.arange(1.0, 1.0 + 19 / 30, 0.01)
    assert all(follower.executing(t) for t in ticks)
    goals = np.array([follower.goal(t) for t in ticks])
    assert goals[:, 0] == pytest.approx((ticks - 1.0) * 30 / 19)
