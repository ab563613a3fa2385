"""A URDF's kinematic tree and its forward kinematics (numpy): joint angles -> parent-to-child transforms.

Reads links and joints (revolute, continuous, prismatic, fixed) with their origin (xyz, rpy), axis
and limits; visuals and the rest are left to the text. `builtin:NAME` names a URDF shipped here.
"""

from __future__ import annotations

import math
import pathlib
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from joshua_runtime.errors import SettingsError

BUILTIN_PREFIX = "builtin:"
BUILTIN_DIR = pathlib.Path(__file__).resolve().parent
MOVABLE = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class Joint:
    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray  # 4x4, parent frame -> joint frame at angle 0
    axis: np.ndarray  # unit vector in the joint frame
    lower: float | None
    upper: float | None

    @property
    def movable(self) -> bool:
        return self.kind in MOVABLE


@dataclass(frozen=True)
class UrdfModel:
    name: str
    text: str
    root: str
    joints: tuple[Joint, ...]

    @property
    def movable_joints(self) -> tuple[Joint, ...]:
        return tuple(joint for joint in self.joints if joint.movable)

    @property
    def fixed_joints(self) -> tuple[Joint, ...]:
        return tuple(joint for joint in self.joints if not joint.movable)

    def joint(self, name: str) -> Joint:
        return next(joint for joint in self.joints if joint.name == name)

    def world_poses(self, positions: dict[str, float]) -> dict[str, np.ndarray]:
        """4x4 pose of every link in the root link's frame (joints missing from `positions` at 0)."""
        poses = {self.root: np.eye(4)}
        pending = list(self.joints)
        while pending:
            ready = [joint for joint in pending if joint.parent in poses]
            for joint in ready:
                poses[joint.child] = poses[joint.parent] @ joint_transform(joint, positions.get(joint.name, 0.0))
                pending.remove(joint)
        return poses


def joint_transform(joint: Joint, position: float) -> np.ndarray:
    """The 4x4 transform from the joint's parent link to its child link at `position` (rad or m)."""
    motion = np.eye(4)
    if joint.kind in ("revolute", "continuous"):
        motion[:3, :3] = axis_angle_matrix(joint.axis, position)
    elif joint.kind == "prismatic":
        motion[:3, 3] = joint.axis * position
    return joint.origin @ motion


def axis_angle_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation matrix about a unit axis."""
    x, y, z = axis
    skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * skew + (1.0 - math.cos(angle)) * skew @ skew


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return (
        axis_angle_matrix(np.array([0.0, 0.0, 1.0]), yaw)
        @ axis_angle_matrix(np.array([0.0, 1.0, 0.0]), pitch)
        @ axis_angle_matrix(np.array([1.0, 0.0, 0.0]), roll)
    )


def quaternion_xyzw(rotation: np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of a rotation matrix, w >= 0."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = (0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s, (m[1, 0] - m[0, 1]) / s)
    sign = -1.0 if q[3] < 0 else 1.0
    return tuple(sign * float(value) for value in q)


def load(reference: str) -> UrdfModel:
    """The model of `builtin:NAME` or of a URDF file path; SettingsError when unreadable."""
    path = (
        BUILTIN_DIR / f"{reference[len(BUILTIN_PREFIX) :]}.urdf"
        if reference.startswith(BUILTIN_PREFIX)
        else pathlib.Path(reference).expanduser()
    )
    try:
        return parse(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SettingsError(f"robot description {reference}: {exc.strerror or exc}") from exc
    except (ET.ParseError, ValueError, KeyError) as exc:
        raise SettingsError(f"robot description {reference} is not a usable URDF: {exc}") from exc


def parse(text: str) -> UrdfModel:
    robot = ET.fromstring(text)
    joints = tuple(_joint(element) for element in robot.findall("joint"))
    links = [link.get("name") for link in robot.findall("link")]
    children = {joint.child for joint in joints}
    roots = [link for link in links if link not in children]
    if len(roots) != 1:
        raise ValueError(f"expected one root link, found {roots or 'none'}")
    return UrdfModel(name=robot.get("name", ""), text=text, root=roots[0], joints=joints)


def _joint(element) -> Joint:
    origin = element.find("origin")
    xyz = _floats(origin.get("xyz") if origin is not None else None, 3)
    rpy = _floats(origin.get("rpy") if origin is not None else None, 3)
    transform = np.eye(4)
    transform[:3, :3] = rpy_matrix(*rpy)
    transform[:3, 3] = xyz
    axis_element = element.find("axis")
    axis = np.array(_floats(axis_element.get("xyz") if axis_element is not None else "1 0 0", 3))
    limit = element.find("limit")
    return Joint(
        name=element.attrib["name"],
        kind=element.attrib["type"],
        parent=element.find("parent").attrib["link"],
        child=element.find("child").attrib["link"],
        origin=transform,
        axis=axis / np.linalg.norm(axis),
        lower=float(limit.get("lower")) if limit is not None and limit.get("lower") else None,
        upper=float(limit.get("upper")) if limit is not None and limit.get("upper") else None,
    )


def _floats(text: str | None, count: int) -> list[float]:
    values = [float(v) for v in text.split()] if text else [0.0] * count
    if len(values) != count:
        raise ValueError(f"expected {count} numbers, got {text!r}")
    return values
