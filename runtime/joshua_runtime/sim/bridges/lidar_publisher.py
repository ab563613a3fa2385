"""LIDAR_PUBLISHER in the simulation: LaserScan of 360 rays at `rate_hz` (LDS-01 geometry, see sim/lidar.py).

The rays are cast in the plane of the site named like the node's frame_id, else site "lidar"; 0.0
where nothing is within 0.12-3.5 m. PointCloud2 when the topic's type says so.
"""

import array

import numpy as np
from sensor_msgs.msg import LaserScan

from joshua_core.settings import NodeSettings
from joshua_runtime.convert.point_cloud import POINT_CLOUD2, laser_scan_to_point_cloud2
from joshua_runtime.nodes import settings_checks
from joshua_runtime.sim import lidar
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.engine import SimulationEngine


class LidarBridge(SimulationBridge):
    """Publishes ray-cast scans like LIDAR_PUBLISHER (as PointCloud2 when the topic's type says so)."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node, self.engine = node, engine
        self.frame_id = settings.frame_id
        self.sensor = lidar.PlanarLidar(engine.model, lidar.lidar_site(engine.model, self.frame_id))
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.as_cloud = settings_checks.topic(settings).message_type == POINT_CLOUD2
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)

    def message(self) -> LaserScan:
        with self.engine.lock:
            ranges = self.sensor.scan(self.engine.data)
        msg = LaserScan()
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        msg.angle_min, msg.angle_max, msg.angle_increment = lidar.ANGLE_MIN, lidar.ANGLE_MAX, lidar.ANGLE_INCREMENT
        msg.time_increment, msg.scan_time = lidar.TIME_INCREMENT_S, lidar.SCAN_TIME_S
        msg.range_min, msg.range_max = lidar.RANGE_MIN_M, lidar.RANGE_MAX_M
        msg.ranges = array.array("f", ranges.astype(np.float32).tobytes())
        msg.intensities = array.array("f", self.sensor.intensities(ranges).astype(np.float32).tobytes())
        return msg

    def publish(self) -> None:
        scan = self.message()
        self.publisher.publish(laser_scan_to_point_cloud2(scan) if self.as_cloud else scan)
