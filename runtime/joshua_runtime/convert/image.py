"""sensor_msgs/Image and sensor_msgs/CompressedImage <-> PerceptionPacket (camera frames).

Raw images keep their encoding and bytes as they are. CompressedImage carries JPEG (or PNG) bytes
with `format` "jpeg"/"png"; decoding gives a bgr8 (or mono8) packet image.
"""

import cv2
import numpy as np
from sensor_msgs.msg import CompressedImage, Image

from joshua_core.schema import PerceptionPacket
from joshua_runtime.convert.stamp import to_proto_timestamp, to_ros_time
from joshua_runtime.errors import SettingsError

IMAGE_TYPE = "sensor_msgs/msg/Image"
COMPRESSED_IMAGE_TYPE = "sensor_msgs/msg/CompressedImage"
JPEG_QUALITY = 90
_EXTENSIONS = {"jpeg": ".jpg", "png": ".png"}
_CHANNELS = {"bgr8": 3, "rgb8": 3, "mono8": 1}


def packet_to_image(packet: PerceptionPacket) -> Image:
    """The packet's image as a raw Image, stamped with the packet's timestamp and frame."""
    source = packet.image
    message = Image()
    message.header.stamp = to_ros_time(packet.timestamp)
    message.header.frame_id = packet.frame_id
    message.height = source.height
    message.width = source.width
    message.encoding = source.encoding
    message.is_bigendian = 0
    message.step = source.step
    message.data = source.data
    return message


def image_to_packet(message: Image) -> PerceptionPacket:
    packet = PerceptionPacket(frame_id=message.header.frame_id)
    to_proto_timestamp(message.header.stamp, packet.timestamp)
    image = packet.image
    image.width = message.width
    image.height = message.height
    image.encoding = message.encoding
    image.step = message.step
    image.data = bytes(message.data)
    return packet


def packet_pixels(packet: PerceptionPacket) -> np.ndarray:
    """The packet's image as a HxWxC (or HxW for mono8) uint8 array (a view, no copy)."""
    image = packet.image
    channels = _CHANNELS.get(image.encoding)
    if channels is None:
        raise ValueError(f"unsupported image encoding {image.encoding!r}")
    rows = np.frombuffer(image.data, np.uint8).reshape(image.height, image.step)
    pixels = rows[:, : image.width * channels]
    return pixels if channels == 1 else pixels.reshape(image.height, image.width, channels)


def packet_to_compressed_image(packet: PerceptionPacket, image_format: str = "jpeg") -> CompressedImage:
    """The packet's image compressed to `image_format` ("jpeg" or "png")."""
    pixels = packet_pixels(packet)
    if packet.image.encoding == "rgb8":
        pixels = cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR)
    params = [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY] if image_format == "jpeg" else []
    ok, encoded = cv2.imencode(_EXTENSIONS[image_format], pixels, params)
    if not ok:
        raise ValueError(f"could not encode the image as {image_format}")
    message = CompressedImage()
    message.header.stamp = to_ros_time(packet.timestamp)
    message.header.frame_id = packet.frame_id
    message.format = image_format
    message.data = encoded.tobytes()
    return message


def compressed_image_to_packet(message: CompressedImage) -> PerceptionPacket:
    pixels = cv2.imdecode(np.frombuffer(bytes(message.data), np.uint8), cv2.IMREAD_UNCHANGED)
    if pixels is None:
        raise ValueError(f"could not decode a {message.format!r} compressed image")
    if pixels.ndim == 3 and pixels.shape[2] == 4:
        pixels = cv2.cvtColor(pixels, cv2.COLOR_BGRA2BGR)
    packet = PerceptionPacket(frame_id=message.header.frame_id)
    to_proto_timestamp(message.header.stamp, packet.timestamp)
    image = packet.image
    image.height, image.width = pixels.shape[:2]
    image.encoding = "mono8" if pixels.ndim == 2 else "bgr8"
    image.step = image.width * (1 if pixels.ndim == 2 else 3)
    image.data = np.ascontiguousarray(pixels).tobytes()
    return packet


def check_message_type(message_type: str) -> None:
    """Raise SettingsError unless a camera can publish `message_type`."""
    if message_type not in (IMAGE_TYPE, COMPRESSED_IMAGE_TYPE):
        raise SettingsError(f"a camera cannot publish {message_type!r} (use {IMAGE_TYPE} or {COMPRESSED_IMAGE_TYPE})")


def packet_to_message(packet: PerceptionPacket, message_type: str):
    """An Image or CompressedImage (JPEG), as `message_type` asks."""
    check_message_type(message_type)
    if message_type == COMPRESSED_IMAGE_TYPE:
        return packet_to_compressed_image(packet)
    return packet_to_image(packet)


def message_to_packet(message) -> PerceptionPacket:
    if isinstance(message, CompressedImage):
        return compressed_image_to_packet(message)
    return image_to_packet(message)
