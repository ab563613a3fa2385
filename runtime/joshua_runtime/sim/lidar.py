"""Simulated LDS-01 planar lidar: 360 rays cast from a model site with mj_multiRay."""

import math

import mujoco
import numpy as np

from joshua_runtime.errors import SettingsError
from joshua_runtime.sim.model import site_id

# LDS-01 facts (ROBOTIS hls_lfcd_lds_driver, hlds_laser_publisher.cpp, and the LDS-01 e-manual).
RAYS = 360
ANGLE_MIN = 0.0
ANGLE_INCREMENT = 2.0 * math.pi / RAYS
ANGLE_MAX = 2.0 * math.pi - ANGLE_INCREMENT
RANGE_MIN_M = 0.12
RANGE_MAX_M = 3.5
RPM = 300.0
TIME_INCREMENT_S = 1.0 / (RPM * 6.0)
SCAN_TIME_S = RAYS * TIME_INCREMENT_S
# Reported for a ray with no return, as the LDS-01 reports a missing reading (0 mm).
NO_RETURN_M = 0.0
# Intensity reported for a ray that hits something (the sensor gives about this for a matt surface).
RETURN_INTENSITY = 1000.0
# Geom groups the rays see: 0 and 1 (group 2 and above hold decoration, e.g. the lidar's own housing).
RAY_GEOM_GROUPS = np.array([1, 1, 0, 0, 0, 0], dtype=np.uint8)
# Site used when the model has no site named after the lidar's frame_id.
DEFAULT_SITE = "lidar"


def lidar_site(model: mujoco.MjModel, frame_id: str) -> int:
    """The site a lidar scans from: the one named like its frame_id, else `lidar`."""
    for name in (frame_id, DEFAULT_SITE):
        if name:
            sid = site_id(model, name)
            if sid >= 0:
                return sid
    raise SettingsError(f"simulation model has no site {frame_id!r} or {DEFAULT_SITE!r} to scan the lidar from")


class PlanarLidar:
    """Casts one ray per degree in the site's x-y plane, counter-clockwise from its +x axis."""

    def __init__(self, model: mujoco.MjModel, site: int):
        self.model = model
        self.site = site
        body = int(model.site_bodyid[site])
        # Rays ignore the body the lidar sits on (never the world body, which holds the static scene).
        self.body_exclude = body if body > 0 else -1
        angles = ANGLE_MIN + ANGLE_INCREMENT * np.arange(RAYS)
        self.local_directions = np.stack([np.cos(angles), np.sin(angles), np.zeros(RAYS)], axis=1)
        self._geom_ids = np.zeros(RAYS, dtype=np.int32)
        self._distances = np.zeros(RAYS, dtype=np.float64)

    def scan(self, data: mujoco.MjData) -> np.ndarray:
        """Ranges in metres, index i at angle i degrees; NO_RETURN_M outside [RANGE_MIN_M, RANGE_MAX_M]."""
        origin = data.site_xpos[self.site].copy()
        rotation = data.site_xmat[self.site].reshape(3, 3)
        directions = (self.local_directions @ rotation.T).ravel()
        mujoco.mj_multiRay(
            self.model,
            data,
            origin,
            directions,
            RAY_GEOM_GROUPS,
            1,
            self.body_exclude,
            self._geom_ids,
            self._distances,
            None,
            RAYS,
            RANGE_MAX_M,
        )
        ranges = self._distances.copy()
        valid = (ranges >= RANGE_MIN_M) & (ranges <= RANGE_MAX_M)
        ranges[~valid] = NO_RETURN_M
        return ranges

    @staticmethod
    def intensities(ranges: np.ndarray) -> np.ndarray:
        """Intensity per ray: RETURN_INTENSITY where the ray hit something, else 0."""
        return np.where(ranges > 0.0, RETURN_INTENSITY, 0.0)
