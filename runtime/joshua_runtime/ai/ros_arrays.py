"""Conversions between sensor_msgs (Image, JointState), trajectory_msgs/JointTrajectory and numpy arrays."""

import cv2
import numpy as np

# Image encodings accepted, with their channel count and their channels' order as OpenCV names it.
_ENCODINGS = {
    "rgb8": (3, "RGB"),
    "bgr8": (3, "BGR"),
    "rgba8": (4, "RGBA"),
    "bgra8": (4, "BGRA"),
    "mono8": (1, "GRAY"),
    "8UC1": (1, "GRAY"),
    "8UC3": (3, "BGR"),  # OpenCV's default channel order is BGR
}


class ImageFormatError(ValueError):
    """An Image message this module cannot turn into an RGB array."""


def image_to_rgb(msg) -> np.ndarray:
    """An (height, width, 3) uint8 RGB array copied from a sensor_msgs/Image or CompressedImage."""
    return _converted(msg, "RGB")


def image_to_bgr(msg) -> np.ndarray:
    """An (height, width, 3) uint8 BGR array (OpenCV's order) copied from a sensor_msgs/Image or CompressedImage."""
    return _converted(msg, "BGR")


def _converted(msg, order: str) -> np.ndarray:
    """The message's pixels in `order` ("RGB" or "BGR"), in one pass over them (a copy or OpenCV's conversion)."""
    if hasattr(msg, "format"):
        pixels, source = _decompress(msg), "BGR"
    else:
        pixels, source = _pixels(msg)
    if source == order:  # a view of the message is copied; a decoded frame is the caller's already
        return pixels if pixels.base is None else pixels.copy()
    return cv2.cvtColor(pixels, getattr(cv2, f"COLOR_{source}2{order}"))


def _pixels(msg) -> tuple[np.ndarray, str]:
    """A view of an Image's pixels, (height, width) or (height, width, channels), and their order."""
    spec = _ENCODINGS.get(msg.encoding)
    if spec is None:
        raise ImageFormatError(f"unsupported image encoding {msg.encoding!r} (supported: {', '.join(_ENCODINGS)})")
    channels, source = spec
    height, width, step = msg.height, msg.width, msg.step
    raw = np.frombuffer(msg.data, dtype=np.uint8)
    if height * width == 0 or step < width * channels or raw.size < step * height:
        raise ImageFormatError(f"image {width}x{height} {msg.encoding} with step {step} has {raw.size} bytes")
    rows = raw[: step * height].reshape(height, step)[:, : width * channels]
    return (rows if channels == 1 else rows.reshape(height, width, channels)), source


def _decompress(msg) -> np.ndarray:
    pixels = cv2.imdecode(np.frombuffer(msg.data, dtype=np.uint8), cv2.IMREAD_COLOR)
    if pixels is None:
        raise ImageFormatError(f"cannot decode compressed image (format {msg.format!r})")
    return pixels


def rgb_to_image(pixels: np.ndarray, stamp=None, frame_id: str = "camera"):
    """A sensor_msgs/Image (rgb8) holding an (height, width, 3) uint8 array."""
    from sensor_msgs.msg import Image

    msg = Image()
    if stamp is not None:
        msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = int(pixels.shape[0]), int(pixels.shape[1])
    msg.encoding = "rgb8"
    msg.is_bigendian = 0
    msg.step = msg.width * 3
    msg.data = np.ascontiguousarray(pixels, dtype=np.uint8).tobytes()
    return msg


def joint_positions(msg) -> tuple[list[str], np.ndarray]:
    """The joint names and float32 positions of a sensor_msgs/JointState."""
    return list(msg.name), np.asarray(msg.position, dtype=np.float32)


def joint_state(names: list[str], positions, stamp=None):
    """A sensor_msgs/JointState with these names and positions (velocity and effort left empty)."""
    from sensor_msgs.msg import JointState

    msg = JointState()
    if stamp is not None:
        msg.header.stamp = stamp
    msg.name = list(names)
    msg.position = [float(value) for value in positions]
    return msg


NANOSECONDS_PER_SECOND = 1_000_000_000


def stamp_seconds(msg) -> float:
    """A message's header stamp in seconds (0.0 when unstamped)."""
    stamp = msg.header.stamp
    return stamp.sec + stamp.nanosec / NANOSECONDS_PER_SECOND


def time_message(seconds: float, message_class=None):
    """A builtin_interfaces Time (or `message_class`, e.g. Duration) of a time in seconds."""
    from builtin_interfaces.msg import Time

    nanoseconds = int(round(seconds * NANOSECONDS_PER_SECOND))
    return (message_class or Time)(
        sec=nanoseconds // NANOSECONDS_PER_SECOND, nanosec=nanoseconds % NANOSECONDS_PER_SECOND
    )


def joint_trajectory(names: list[str], chunk: np.ndarray, stamp_s: float, step_s: float):
    """An action chunk (steps x joints) as a trajectory_msgs/JointTrajectory: point i at i * step_s after stamp_s."""
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    msg = JointTrajectory()
    msg.header.stamp = time_message(stamp_s)
    msg.joint_names = list(names)
    msg.points = [
        JointTrajectoryPoint(positions=[float(v) for v in row], time_from_start=time_message(i * step_s, Duration))
        for i, row in enumerate(chunk)
    ]
    return msg
