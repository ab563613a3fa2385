"""MOCK_LIDAR_PUBLISHER: scans of the synthetic room (no serial port), at rate_hz, as LaserScan or
PointCloud2 (the topic's message_type).

The scans are what an LDS-01 at 300 rpm would report from the middle of the emulators' synthetic
room: whole-degree rays, 0 where the wall is beyond 3.5 m.
"""

import time

from joshua_runtime.convert.point_cloud import scan_message
from joshua_runtime.drivers import lds01_protocol, synthetic_room
from joshua_runtime.drivers.lds01 import scan_packet
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks


class MockLidarPublisher(JoshuaNode):
    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        period = settings_checks.period_s(self.settings)
        ranges_mm = synthetic_room.scan_mm()
        self.ranges = [mm / 1000.0 for mm in ranges_mm]
        self.intensities = [float(synthetic_room.intensity(mm)) for mm in ranges_mm]
        self.frame_id = self.settings.frame_id
        self.scans = self.publisher(topic)
        self.message_type = topic.message_type
        self.ros.create_timer(period, self._publish)

    def _publish(self) -> None:
        packet = scan_packet(self.ranges, self.intensities, lds01_protocol.NOMINAL_RPM, self.frame_id, time.time_ns())
        self.scans.publish(scan_message(packet, self.message_type))
