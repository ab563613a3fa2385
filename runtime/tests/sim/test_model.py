"""The built-in SO-100 MJCF: joints, ranges, actuators, sensors' anchors, and model loading errors."""

import mujoco
import pytest
from sim_settings import SO100_RANGES

from joshua_runtime.errors import SettingsError
from joshua_runtime.sim.model import BUILTIN_MODEL_FILES, camera_id, joint_names, load_model, model_path


@pytest.fixture(scope="module")
def so100():
    return load_model("builtin:so100")


def test_builtin_name_maps_to_the_packaged_file():
    assert model_path("builtin:so100") == BUILTIN_MODEL_FILES["so100"]
    assert model_path("builtin:so100").name == "so100.xml"


def test_six_hinge_joints_with_the_arm_ranges(so100):
    assert joint_names(so100) == list(SO100_RANGES)
    for name, (low, high) in SO100_RANGES.items():
        joint = so100.joint(name)
        assert joint.type[0] == mujoco.mjtJoint.mjJNT_HINGE
        assert joint.limited[0] == 1
        assert tuple(joint.range) == pytest.approx((low, high))


def test_every_joint_has_a_position_actuator_limited_to_its_range(so100):
    assert so100.nu == 6
    for aid, (name, (low, high)) in enumerate(SO100_RANGES.items()):
        actuator = so100.actuator(aid)
        assert actuator.name == name
        assert actuator.trntype[0] == mujoco.mjtTrn.mjTRN_JOINT
        assert so100.joint(actuator.trnid[0]).name == name
        assert tuple(actuator.ctrlrange) == pytest.approx((low, high))
        # A position servo: force = kp * (ctrl - q) - kv * qdot.
        assert actuator.gainprm[0] > 0 and actuator.biasprm[1] == -actuator.gainprm[0]


def test_scene_has_cameras_lidar_site_table_and_a_free_cube(so100):
    assert [so100.camera(c).name for c in range(so100.ncam)] == ["front", "wrist"]
    assert camera_id(so100, "") == 0
    assert camera_id(so100, "wrist") == 1
    assert mujoco.mj_name2id(so100, mujoco.mjtObj.mjOBJ_SITE, "lidar") >= 0
    assert mujoco.mj_name2id(so100, mujoco.mjtObj.mjOBJ_GEOM, "table_top") >= 0
    cube = so100.joint("cube")
    assert cube.type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert so100.nlight >= 1
    assert so100.opt.timestep == pytest.approx(0.002)


def test_collision_geometry_is_primitives_only(so100):
    primitives = {
        mujoco.mjtGeom.mjGEOM_PLANE,
        mujoco.mjtGeom.mjGEOM_BOX,
        mujoco.mjtGeom.mjGEOM_CAPSULE,
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        mujoco.mjtGeom.mjGEOM_SPHERE,
    }
    assert {mujoco.mjtGeom(int(t)) for t in so100.geom_type} <= primitives
    assert so100.nmesh == 0


def test_timestep_override(so100):
    assert load_model("builtin:so100", 0.005).opt.timestep == pytest.approx(0.005)


def test_camera_lookup_names_the_known_cameras(so100):
    with pytest.raises(SettingsError, match=r"no camera 'top' \(cameras: front, wrist\)"):
        camera_id(so100, "top")


@pytest.mark.parametrize(
    "spec, message",
    [
        ("", r"simulation model is not set"),
        (
            "builtin:so101",
            r"unknown built-in simulation model 'builtin:so101' \(known: builtin:lego_bot, builtin:so100\)",
        ),
        ("missing.xml", r"simulation model 'missing.xml' does not exist"),
    ],
)
def test_unusable_model_names(spec, message):
    with pytest.raises(SettingsError, match=message):
        load_model(spec)


def test_invalid_mjcf_is_one_settings_error(tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text("<mujoco><worldbody><body><joint type='hinge'/></worldbody></mujoco>")
    with pytest.raises(SettingsError, match=r"does not load: ") as caught:
        load_model(str(broken))
    assert "\n" not in str(caught.value)


def test_non_positive_timestep_is_rejected():
    with pytest.raises(SettingsError, match=r"timestep_s must be positive, got 0.0"):
        load_model("builtin:so100", 0.0)
