"""Planar scan readings as 3D points (numpy only), for a PerceptionPacket's point_cloud.

A reading at angle a and range r is the point (r cos a, r sin a, 0) in the scan's frame; readings
outside [range_min, range_max] (the LDS-01 reports 0 for "no echo") are no point.
"""

from __future__ import annotations

import numpy as np

from joshua_core.schema import PerceptionPacket


def scan_points(
    ranges, intensities, angle_min: float, angle_increment: float, range_min: float, range_max: float
) -> tuple[np.ndarray, np.ndarray]:
    """(N x 3 float32 points, N float32 intensities) of the valid readings of a scan."""
    ranges = np.asarray(ranges, dtype=np.float64)
    angles = angle_min + angle_increment * np.arange(len(ranges))
    valid = np.isfinite(ranges) & (ranges >= range_min) & (ranges <= range_max)
    xyz = np.stack([ranges * np.cos(angles), ranges * np.sin(angles), np.zeros_like(ranges)], axis=1)[valid]
    intensity = np.asarray(intensities, dtype=np.float32)
    intensity = intensity[valid] if len(intensity) == len(ranges) else np.zeros(int(valid.sum()), np.float32)
    return xyz.astype(np.float32), intensity


def fill_point_cloud(packet: PerceptionPacket) -> None:
    """Set the packet's point_cloud from its scan readings (packet.sensor)."""
    sensor = packet.sensor
    xyz, intensity = scan_points(
        sensor.ranges, sensor.intensities, sensor.angle_min, sensor.angle_increment, sensor.range_min, sensor.range_max
    )
    cloud = packet.point_cloud
    del cloud.xyz[:], cloud.intensity[:]
    cloud.xyz.extend(xyz.ravel().tolist())
    cloud.intensity.extend(intensity.tolist())
