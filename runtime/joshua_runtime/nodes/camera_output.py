"""Where a camera node publishes each frame: its topic, and a JPEG copy for readers on other hosts.

joshuac names the copy (`compressed_topic`, `<topic>/compressed`, sensor_msgs/msg/CompressedImage) only
for a robot on several hosts whose camera images are read on another host; the copy is encoded only
while something subscribes to it.
"""

from joshua_runtime.convert.image import COMPRESSED_IMAGE_TYPE, check_message_type, packet_to_message


class CameraOutput:
    """The publishers of one camera node's frames."""

    def __init__(self, node, topic, compressed_topic) -> None:
        self.message_type = topic.message_type
        check_message_type(self.message_type)
        self.images = node.publisher(topic)
        self.compressed = node.publisher(compressed_topic) if compressed_topic.name else None

    def publish(self, packet) -> None:
        self.images.publish(packet_to_message(packet, self.message_type))
        if self.compressed is not None and self.compressed.get_subscription_count() > 0:
            self.compressed.publish(packet_to_message(packet, COMPRESSED_IMAGE_TYPE))
