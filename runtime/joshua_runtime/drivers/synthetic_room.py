"""A synthetic room seen by a planar lidar: ray-cast distances to the walls of a box-furnished room.

The lidar sits at the origin; x points forward, y to the left, angles grow counter-clockwise
(REP-103). The room is the rectangle ROOM (x_min, x_max, y_min, y_max) in metres with one box
BOX inside it. With the defaults:

    angle 0    -> the box front face at 0.8 m
    angle 90   -> the left wall at 1.5 m
    angle 180  -> the back wall at 4.0 m: beyond 3.5 m, so reported as 0 (out of range)
    angle 270  -> the right wall at 1.0 m
"""

import math

from joshua_runtime.drivers.lds01_protocol import RANGE_MAX_M, RANGE_MIN_M, READINGS_PER_TURN

ROOM = (-4.0, 2.0, -1.0, 1.5)
BOX = (0.8, 1.2, -0.2, 0.2)
# Intensity model: strong when near, fading with distance; 0 when out of range.
INTENSITY_AT_ZERO = 4000


def _ray_to_inside_of(rect, cos_a: float, sin_a: float) -> float:
    """Distance from the origin (inside rect) to where the ray leaves rect."""
    x_min, x_max, y_min, y_max = rect
    hits = []
    if cos_a > 1e-12:
        hits.append(x_max / cos_a)
    elif cos_a < -1e-12:
        hits.append(x_min / cos_a)
    if sin_a > 1e-12:
        hits.append(y_max / sin_a)
    elif sin_a < -1e-12:
        hits.append(y_min / sin_a)
    return min(hits)


def _ray_to_outside_of(rect, cos_a: float, sin_a: float) -> float:
    """Distance from the origin (outside rect) to where the ray enters rect, or inf (slab method)."""
    t_near, t_far = 0.0, math.inf
    for low, high, direction in ((rect[0], rect[1], cos_a), (rect[2], rect[3], sin_a)):
        if abs(direction) < 1e-12:
            if not low <= 0.0 <= high:
                return math.inf
            continue
        t1, t2 = sorted((low / direction, high / direction))
        t_near, t_far = max(t_near, t1), min(t_far, t2)
    return t_near if t_near <= t_far else math.inf


def distance_m(angle_rad: float, room=ROOM, box=BOX) -> float:
    """True distance along the ray at `angle_rad` to the first wall or box face."""
    cos_a, sin_a = math.cos(angle_rad), math.sin(angle_rad)
    return min(_ray_to_inside_of(room, cos_a, sin_a), _ray_to_outside_of(box, cos_a, sin_a))


def range_mm(angle_deg: int) -> int:
    """What the lidar reports at a whole-degree angle: millimetres, 0 outside 0.12-3.5 m."""
    distance = distance_m(math.radians(angle_deg))
    if not RANGE_MIN_M <= distance <= RANGE_MAX_M:
        return 0
    return int(round(distance * 1000.0))


def intensity(range_in_mm: int) -> int:
    """Reported intensity of a reading of `range_in_mm` (0 when out of range)."""
    return 0 if range_in_mm == 0 else max(1, INTENSITY_AT_ZERO - range_in_mm)


def scan_mm() -> list[int]:
    """Ranges in millimetres of one turn, indexed by angle in degrees (0..359)."""
    return [range_mm(angle) for angle in range(READINGS_PER_TURN)]
