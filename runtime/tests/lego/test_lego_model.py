"""builtin:lego_bot: the wheels' velocity actuators drive the car as the base's kinematics say."""

import math

import mujoco
import pytest

from joshua_runtime.odometry import Geometry
from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.model import load_model

LEGO = Geometry(wheel_radius_m=0.028, track_width_m=0.12)


@pytest.fixture
def engine():
    return SimulationEngine(load_model("builtin:lego_bot"), realtime_factor=0)


def drive(engine, linear, angular, seconds):
    wheels = engine.joints(["left_wheel", "right_wheel"], actuated=True)
    engine.command(wheels, LEGO.wheel_speeds(linear, angular))
    engine.step(int(seconds / engine.model.opt.timestep))
    return engine.data.qpos[:7].copy()


def test_equal_wheel_speeds_drive_straight_ahead(engine):
    pose = drive(engine, 0.1, 0.0, 3.0)
    assert 0.27 < pose[0] < 0.31 and abs(pose[1]) < 0.005


def test_opposite_wheel_speeds_turn_left_on_the_spot(engine):
    pose = drive(engine, 0.0, 1.0, 1.5)
    yaw = 2 * math.atan2(pose[6], pose[3])
    assert 1.1 < yaw < 1.6 and math.hypot(pose[0], pose[1]) < 0.02


def test_the_distance_sensor_sees_the_wall_ahead(engine):
    mujoco.mj_forward(engine.model, engine.data)
    assert engine.data.sensor("distance").data[0] == pytest.approx(1.43, abs=0.02)
