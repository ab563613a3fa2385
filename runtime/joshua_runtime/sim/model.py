"""Loading of the simulated world: `builtin:NAME` or an MJCF path, with clear errors."""

from pathlib import Path

import mujoco

from joshua_core.models import BUILTIN_MODELS, BUILTIN_PREFIX
from joshua_runtime.errors import SettingsError

MODELS_DIR = Path(__file__).resolve().parent / "models"
BUILTIN_MODEL_FILES = {name: MODELS_DIR / f"{name}.xml" for name in BUILTIN_MODELS}
# Joint types a JointState can carry (one coordinate each).
_MOVABLE_JOINT_TYPES = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


def model_path(spec: str) -> Path:
    """The MJCF file named by `builtin:so100` or by a path (relative paths: from the working directory)."""
    if not spec:
        raise SettingsError("simulation model is not set (use builtin:so100 or an MJCF path)")
    if spec.startswith(BUILTIN_PREFIX):
        name = spec[len(BUILTIN_PREFIX) :]
        if name not in BUILTIN_MODEL_FILES:
            known = ", ".join(BUILTIN_PREFIX + n for n in sorted(BUILTIN_MODEL_FILES))
            raise SettingsError(f"unknown built-in simulation model {spec!r} (known: {known})")
        return BUILTIN_MODEL_FILES[name]
    path = Path(spec).expanduser()
    if not path.is_file():
        raise SettingsError(f"simulation model {spec!r} does not exist")
    return path


def load_model(spec: str, timestep_s: float | None = None) -> mujoco.MjModel:
    """Compile the MJCF model; `timestep_s` (when given) replaces the model's own timestep."""
    path = model_path(spec)
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        message = str(exc).strip().replace("\n", " ")
        raise SettingsError(f"simulation model {spec!r} does not load: {message}") from exc
    if timestep_s is not None:
        if not timestep_s > 0:
            raise SettingsError(f"simulation timestep_s must be positive, got {timestep_s}")
        model.opt.timestep = timestep_s
    return model


def joint_id(model: mujoco.MjModel, name: str) -> int:
    """Id of the hinge or slide joint called `name`, or a SettingsError naming the known joints."""
    jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
    if jid < 0 or int(model.jnt_type[jid]) not in _MOVABLE_JOINT_TYPES:
        raise SettingsError(
            f"simulation model has no hinge or slide joint {name!r} (joints: {', '.join(joint_names(model))})"
        )
    return jid


def joint_names(model: mujoco.MjModel) -> list[str]:
    """Names of the model's hinge and slide joints, in model order."""
    return [model.joint(j).name for j in range(model.njnt) if int(model.jnt_type[j]) in _MOVABLE_JOINT_TYPES]


def position_actuator(model: mujoco.MjModel, jid: int) -> int:
    """Id of the actuator that drives joint `jid` directly, or a SettingsError."""
    for aid in range(model.nu):
        if int(model.actuator_trntype[aid]) == int(mujoco.mjtTrn.mjTRN_JOINT) and model.actuator_trnid[aid, 0] == jid:
            return aid
    raise SettingsError(f"simulation model has no actuator on joint {model.joint(jid).name!r}")


def camera_id(model: mujoco.MjModel, name: str) -> int:
    """Id of the camera called `name` ("" = the model's first camera), or a SettingsError."""
    if model.ncam == 0:
        raise SettingsError("simulation model has no camera to render")
    if not name:
        return 0
    cid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, name)
    if cid < 0:
        known = ", ".join(model.camera(c).name for c in range(model.ncam))
        raise SettingsError(f"simulation model has no camera {name!r} (cameras: {known})")
    return cid


def site_id(model: mujoco.MjModel, name: str) -> int:
    """Id of the site called `name`, or -1."""
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
