"""MOCK_CAMERA_PUBLISHER: a synthetic moving pattern at width x height, rate_hz, as Image or CompressedImage.

Frame n is a colour gradient (blue grows left to right, green top to bottom, red constant)
scrolled right by n x SCROLL_PX pixels, so a viewer sees motion and a test can recover n.
"""

import time

import numpy as np

from joshua_runtime.drivers.camera import frame_to_packet
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.camera_output import CameraOutput

SCROLL_PX = 8
RED_LEVEL = 128


def gradient(width: int, height: int) -> np.ndarray:
    """Frame 0 of the pattern, HxWx3 BGR."""
    frame = np.empty((height, width, 3), np.uint8)
    frame[:, :, 0] = (np.arange(width) * 255 // max(width - 1, 1)).astype(np.uint8)[None, :]
    frame[:, :, 1] = (np.arange(height) * 255 // max(height - 1, 1)).astype(np.uint8)[:, None]
    frame[:, :, 2] = RED_LEVEL
    return frame


def pattern_frame(base: np.ndarray, n: int) -> np.ndarray:
    """Frame n of the pattern: frame 0 scrolled right by n x SCROLL_PX pixels."""
    return np.roll(base, (n * SCROLL_PX) % base.shape[1], axis=1)


class MockCameraPublisher(JoshuaNode):
    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        period = settings_checks.period_s(self.settings)
        width, height = settings_checks.image_size(self.settings)
        self.output = CameraOutput(self, topic, self.settings.compressed_topic)
        self.frame_id = self.settings.frame_id
        self.base = gradient(width, height)
        self.frame_number = 0
        self.ros.create_timer(period, self._publish)

    def _publish(self) -> None:
        frame = pattern_frame(self.base, self.frame_number)
        self.frame_number += 1
        packet = frame_to_packet(frame, self.frame_id, time.time_ns())
        self.output.publish(packet)
