"""The SO-100 URDF agrees with the MuJoCo model: joints, axes and limits, and forward kinematics."""

import mujoco
import numpy as np
import pytest

from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.description.urdf_model import load, quaternion_xyzw
from joshua_runtime.sim.model import BUILTIN_MODEL_FILES

CONFIGURATIONS = [
    dict.fromkeys(SO100_JOINTS, 0.0),
    {
        "shoulder_pan": 0.7,
        "shoulder_lift": -0.4,
        "elbow_flex": 1.1,
        "wrist_flex": -0.9,
        "wrist_roll": 2.0,
        "gripper": 1.2,
    },
    {
        "shoulder_pan": -1.5,
        "shoulder_lift": 1.2,
        "elbow_flex": -1.3,
        "wrist_flex": 0.5,
        "wrist_roll": -2.5,
        "gripper": -0.1,
    },
]


@pytest.fixture(scope="module")
def mujoco_model():
    return mujoco.MjModel.from_xml_path(str(BUILTIN_MODEL_FILES["so100"]))


@pytest.fixture(scope="module")
def urdf():
    return load("builtin:so100")


def test_joint_names_axes_and_limits_match_the_mujoco_model(mujoco_model, urdf):
    assert [joint.name for joint in urdf.movable_joints] == list(SO100_JOINTS)
    for joint in urdf.movable_joints:
        mj = mujoco_model.joint(joint.name)
        assert joint.kind == "revolute" and mj.type[0] == mujoco.mjtJoint.mjJNT_HINGE
        assert joint.axis == pytest.approx(mj.axis)
        assert (joint.lower, joint.upper) == pytest.approx(tuple(mj.range))
        assert joint.child == mujoco_model.body(mj.bodyid[0]).name
    assert urdf.root == "base_link"


@pytest.mark.parametrize("positions", CONFIGURATIONS)
def test_forward_kinematics_matches_mujoco_body_poses(mujoco_model, urdf, positions):
    data = mujoco.MjData(mujoco_model)
    for name, value in positions.items():
        data.qpos[mujoco_model.joint(name).qposadr[0]] = value
    mujoco.mj_kinematics(mujoco_model, data)
    base = mujoco_model.body("base").id
    poses = urdf.world_poses(positions)
    for joint in urdf.movable_joints:
        body = mujoco_model.body(joint.child).id
        assert poses[joint.child][:3, 3] == pytest.approx(data.xpos[body] - data.xpos[base], abs=1e-9)
        w, x, y, z = data.xquat[body]
        expected = np.array([x, y, z, w]) * (1 if w >= 0 else -1)
        assert np.array(quaternion_xyzw(poses[joint.child][:3, :3])) == pytest.approx(expected, abs=1e-9)
    laser = data.site_xpos[mujoco_model.site("lidar").id]
    assert poses["laser"][:3, 3] == pytest.approx(laser, abs=1e-9)
