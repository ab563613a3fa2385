"""LIDAR_PUBLISHER: LDS-01 turns read from serial_port, published as LaserScan or PointCloud2 (the topic's
message_type), one per turn, 5 Hz.

A reader thread assembles turns (the driver blocks up to a turn, 0.2 s) and publishes each one, so
the executor stays free to notice a stop signal. A driver failure (missing port, silent device)
is handed to the executor by a watchdog timer and ends the node with exit code 3.
"""

import threading

from joshua_runtime.convert.point_cloud import scan_message
from joshua_runtime.drivers.lds01 import Lds01Driver
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks

WATCHDOG_PERIOD_S = 0.05
READER_JOIN_TIMEOUT_S = 0.3


class LidarPublisher(JoshuaNode):
    lidar = None
    reader = None
    ready_later = True  # ready once the first whole turn is published: a silent device is never ready

    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        port = self.settings.serial_port
        if not port:
            raise SettingsError("LIDAR_PUBLISHER needs a serial_port")
        self.lidar = Lds01Driver(
            port,
            baud_rate=self.settings.baud_rate,
            frame_id=self.settings.frame_id,
        )
        self.lidar.open()
        self.scans = self.publisher(topic)
        self.message_type = topic.message_type
        self.stopping = threading.Event()
        self.failure: JoshuaError | None = None
        self.reader = threading.Thread(target=self._read_turns, name="lds01-reader", daemon=True)
        self.reader.start()
        self.ros.create_timer(WATCHDOG_PERIOD_S, self._raise_reader_failure)

    def _read_turns(self) -> None:
        try:
            while not self.stopping.is_set():
                scan = self.lidar.read_scan(should_stop=self.stopping.is_set)
                if scan is not None:
                    self.scans.publish(scan_message(scan, self.message_type))
                    self.announce_ready("first scan published")
        except JoshuaError as exc:
            self.failure = exc

    def _raise_reader_failure(self) -> None:
        if self.failure is not None:
            raise self.failure

    def close(self) -> None:
        if self.reader is not None:
            self.stopping.set()
            self.reader.join(READER_JOIN_TIMEOUT_S)
        if self.lidar is not None:
            self.lidar.close()
