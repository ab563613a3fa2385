"""CAMERA_PUBLISHER: frames of an OpenCV camera (device index or video_source) as Image or CompressedImage.

Every 1/rate_hz one frame is read at width x height and published on `topic`, stamped when it was
read, with the node's frame_id. A camera that cannot be opened or stops delivering frames ends the
node with exit code 3.
"""

from joshua_runtime.convert.image import check_message_type, packet_to_message
from joshua_runtime.drivers.camera import CameraDriver
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks


class CameraPublisher(JoshuaNode):
    camera = None

    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        period = settings_checks.period_s(self.settings)
        width, height = settings_checks.image_size(self.settings)
        self.message_type = topic.message_type
        check_message_type(self.message_type)
        self.camera = CameraDriver(
            camera_index=self.settings.camera_index,
            video_source=self.settings.video_source,
            width=width,
            height=height,
            fps=self.settings.rate_hz,
            frame_id=self.settings.frame_id,
        )
        self.camera.open()
        self.images = self.publisher(topic)
        self.ros.create_timer(period, self._publish)

    def _publish(self) -> None:
        self.images.publish(packet_to_message(self.camera.read(), self.message_type))

    def close(self) -> None:
        if self.camera is not None:
            self.camera.close()
