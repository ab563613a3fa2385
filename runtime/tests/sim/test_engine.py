"""The ROS-free engine: position tracking, clamping, the real-time thread, and lidar ray casts."""

import math
import time

import mujoco
import numpy as np
import pytest

from joshua_core import so100
from joshua_runtime.errors import SettingsError
from joshua_runtime.sim import lidar
from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.model import load_model

JOINTS = list(so100.SO100_JOINTS)
# A pose clear of the table, away from zero on every joint.
GOAL = [0.8, 0.3, 0.2, -0.4, 1.2, 0.7]
TRACKING_TOLERANCE_RAD = 0.01
SETTLE_STEPS = 1000  # 2 s at the model's 2 ms timestep
# Wall-clock budget for the threaded engine to reach GOAL at realtime factor 0 (as fast as possible).
THREAD_SETTLE_TIMEOUT_S = 20.0


@pytest.fixture
def engine():
    engine = SimulationEngine(load_model("builtin:so100"))
    yield engine
    engine.stop()


def test_arm_holds_its_initial_pose_without_commands(engine):
    arm = engine.joints(JOINTS)
    engine.step(SETTLE_STEPS)
    assert engine.read(arm).positions == pytest.approx([0.0] * 6, abs=TRACKING_TOLERANCE_RAD)


def test_joints_converge_to_commanded_positions(engine):
    arm = engine.joints(JOINTS, actuated=True)
    engine.command(arm, GOAL)
    engine.step(SETTLE_STEPS)
    reading = engine.read(arm)
    assert reading.positions == pytest.approx(GOAL, abs=TRACKING_TOLERANCE_RAD)
    assert np.abs(reading.velocities).max() < 0.01
    assert reading.sim_time == pytest.approx(SETTLE_STEPS * 0.002)


@pytest.mark.parametrize("timestep_s", [0.001, 0.005])
def test_tracking_is_stable_at_other_timesteps(timestep_s):
    engine = SimulationEngine(load_model("builtin:so100", timestep_s))
    arm = engine.joints(JOINTS, actuated=True)
    engine.command(arm, GOAL)
    engine.step(round(2.0 / timestep_s))
    assert engine.read(arm).positions == pytest.approx(GOAL, abs=TRACKING_TOLERANCE_RAD)


def test_commands_are_clamped_to_the_joint_range_and_nan_keeps_a_goal(engine):
    arm = engine.joints(JOINTS, actuated=True)
    engine.command(arm, [5.0, -5.0, math.nan, math.nan, math.nan, math.nan])
    assert engine.data.ctrl.tolist() == pytest.approx([1.92, -1.75, 0.0, 0.0, 0.0, 0.0])
    engine.command(arm, [math.nan, math.nan, 0.3, math.nan, math.nan, -1.0])
    assert engine.data.ctrl.tolist() == pytest.approx([1.92, -1.75, 0.3, 0.0, 0.0, -0.17])


def test_subset_and_order_follow_the_node_joint_names(engine):
    wrist = engine.joints(["gripper", "wrist_roll"], actuated=True)
    engine.command(wrist, [0.5, -1.0])
    engine.step(SETTLE_STEPS)
    assert engine.read(wrist).positions == pytest.approx([0.5, -1.0], abs=TRACKING_TOLERANCE_RAD)
    assert engine.read(engine.joints(["shoulder_pan"])).positions == pytest.approx([0.0], abs=TRACKING_TOLERANCE_RAD)


def test_unknown_joint_names_the_model_joints(engine):
    with pytest.raises(SettingsError, match=r"no hinge or slide joint 'elbow' \(joints: shoulder_pan, .*, gripper\)"):
        engine.joints(["elbow"])
    with pytest.raises(SettingsError, match=r"no hinge or slide joint 'cube'"):
        engine.joints(["cube"])


def test_negative_realtime_factor_is_rejected():
    with pytest.raises(SettingsError, match=r"realtime_factor must be >= 0, got -1"):
        SimulationEngine(load_model("builtin:so100"), realtime_factor=-1)


def test_physics_thread_runs_and_stops(engine):
    engine.realtime_factor = 0.0
    arm = engine.joints(JOINTS, actuated=True)
    engine.command(arm, GOAL)
    engine.start()
    deadline = time.monotonic() + THREAD_SETTLE_TIMEOUT_S
    while engine.sim_time < 2.0 and time.monotonic() < deadline:
        time.sleep(0.01)
    engine.stop()
    stopped_at = engine.sim_time
    assert stopped_at >= 2.0
    assert engine.read(arm).positions == pytest.approx(GOAL, abs=TRACKING_TOLERANCE_RAD)
    time.sleep(0.05)
    assert engine.sim_time == stopped_at


def test_lidar_ranges_match_the_room(engine):
    model = engine.model
    sensor = lidar.PlanarLidar(model, lidar.lidar_site(model, "laser"))
    ranges = sensor.scan(engine.data)
    assert ranges.shape == (360,)
    assert ((ranges >= lidar.RANGE_MIN_M) & (ranges <= lidar.RANGE_MAX_M)).all()
    # The site is at (-0.25, 0.28); wall inner faces are at x = +-1.48 and y = +-1.48.
    assert ranges[0] == pytest.approx(1.48 + 0.25)
    assert ranges[90] == pytest.approx(1.48 - 0.28)
    assert ranges[180] == pytest.approx(1.48 - 0.25)
    assert ranges[270] == pytest.approx(1.48 + 0.28)
    # Towards the arm's base (radius 0.045 at the origin), about 312 degrees.
    assert ranges[312] == pytest.approx(math.hypot(0.25, 0.28) - 0.045, abs=0.005)
    assert sensor.intensities(ranges).tolist() == [lidar.RETURN_INTENSITY] * 360


def test_lidar_sees_the_cube_move(engine):
    model = engine.model
    sensor = lidar.PlanarLidar(model, lidar.lidar_site(model, "lidar"))
    cube = model.joint("cube").qposadr[0]
    bearing = round(math.degrees(math.atan2(0.06 - 0.28, 0.22 + 0.25))) % 360
    before = sensor.scan(engine.data)[bearing]
    assert before == pytest.approx(math.hypot(0.47, 0.22) - 0.015, abs=0.01)
    engine.data.qpos[cube : cube + 3] = [0.22, -1.0, 0.015]  # move it out of the beam
    engine.step(1)
    assert sensor.scan(engine.data)[bearing] > 1.0


def test_lidar_site_is_the_frame_id_else_lidar_else_an_error(engine):
    assert lidar.lidar_site(engine.model, "laser") == lidar.lidar_site(engine.model, "lidar") >= 0
    bare = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom type='plane' size='1 1 .1'/></worldbody></mujoco>")
    with pytest.raises(SettingsError, match=r"no site 'base_scan' or 'lidar' to scan the lidar from"):
        lidar.lidar_site(bare, "base_scan")
