"""CAMERA_PUBLISHER in the simulation: rendered frames at `width` x `height`, `rate_hz`.

Image with encoding rgb8 (MuJoCo renders RGB), or CompressedImage (JPEG) when the topic's type says
so. The model camera is the one named like the node's frame_id, else the simulation's `camera`.
Frames are drawn by the engine's render thread (sim/cameras.py), which serves the bridge's stream.
"""

import array

import cv2
import numpy as np
from sensor_msgs.msg import CompressedImage, Image

from joshua_core.settings import NodeSettings
from joshua_runtime.nodes import settings_checks
from joshua_runtime.sim.bridge import SimulationBridge
from joshua_runtime.sim.cameras import CameraStream
from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.model import camera_id

IMAGE_ENCODING = "rgb8"
JPEG_FORMAT = "rgb8; jpeg compressed bgr8"
JPEG_QUALITY = 90


class CameraBridge(SimulationBridge):
    """Publishes rendered frames like CAMERA_PUBLISHER; `stream` is handed to the CameraThread."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node = node
        self.name = settings.name
        self.frame_id = settings.frame_id
        width, height = settings_checks.image_size(settings)
        topic = settings_checks.topic(settings)
        self.compressed = topic.message_type.endswith("/CompressedImage")
        self.publisher = node.publisher(topic)
        camera = _camera_for(engine, self.frame_id, node.default_camera)
        self.stream = CameraStream(camera, width, height, 1.0 / settings_checks.period_s(settings), self.publish)

    @property
    def streams(self) -> tuple[CameraStream, ...]:
        return (self.stream,)

    def summary(self) -> str:
        return f"{self.name} {self.stream.frames} frames ({self.stream.skipped} skipped)"

    def publish(self, pixels: np.ndarray, _sim_time: float) -> None:
        if self.compressed:
            msg = CompressedImage()
            msg.format = JPEG_FORMAT
            ok, encoded = cv2.imencode(
                ".jpg", cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY]
            )
            if not ok:
                return
            msg.data = array.array("B", encoded.tobytes())
        else:
            msg = Image()
            msg.height, msg.width = pixels.shape[0], pixels.shape[1]
            msg.encoding = IMAGE_ENCODING
            msg.is_bigendian = 0
            msg.step = pixels.shape[1] * 3
            msg.data = array.array("B", pixels.tobytes())
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        self.publisher.publish(msg)


def _camera_for(engine: SimulationEngine, frame_id: str, default_camera: str) -> int:
    """The model camera named like the node's frame_id, else the simulation's camera setting."""
    model = engine.model
    if frame_id and any(model.camera(c).name == frame_id for c in range(model.ncam)):
        return camera_id(model, frame_id)
    return camera_id(model, default_camera)
