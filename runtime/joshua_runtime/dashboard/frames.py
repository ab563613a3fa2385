"""ROS messages turned into the JSON the page draws: joint states, JPEG camera frames, lidar scans."""

import base64
import math

import cv2

from joshua_runtime.ai.ros_arrays import image_to_bgr

# Frames wider than this are scaled down before JPEG encoding (the page shows them at most this wide).
MAX_IMAGE_WIDTH = 640
JPEG_QUALITY = 75


def stamp_ns(message) -> int:
    """The message header's stamp in nanoseconds (0 when the publisher left it empty)."""
    stamp = message.header.stamp
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def _finite(values) -> list:
    """Floats for JSON: NaN and infinities become null."""
    return [float(v) if math.isfinite(v) else None for v in values]


def joint_state_event(topic: str, message) -> dict:
    return {
        "topic": topic,
        "stamp_ns": stamp_ns(message),
        "name": list(message.name),
        "position": _finite(message.position),
        "velocity": _finite(message.velocity),
        "effort": _finite(message.effort),
    }


def image_event(topic: str, message) -> dict:
    """The frame as a base64 JPEG, scaled down to MAX_IMAGE_WIDTH when wider."""
    bgr = image_to_bgr(message)  # OpenCV encodes BGR: one conversion from the message's order
    height, width = bgr.shape[:2]
    if width > MAX_IMAGE_WIDTH:
        scale = MAX_IMAGE_WIDTH / width
        bgr = cv2.resize(bgr, (MAX_IMAGE_WIDTH, max(1, round(height * scale))), interpolation=cv2.INTER_AREA)
    ok, jpeg = cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
    if not ok:
        raise ValueError(f"JPEG encoding of a {width}x{height} frame failed")
    return {
        "topic": topic,
        "stamp_ns": stamp_ns(message),
        "width": width,
        "height": height,
        "jpeg": base64.b64encode(jpeg.tobytes()).decode("ascii"),
    }


def scan_event(topic: str, message) -> dict:
    return {
        "topic": topic,
        "stamp_ns": stamp_ns(message),
        "angle_min": message.angle_min,
        "angle_increment": message.angle_increment,
        "range_max": message.range_max,
        "ranges": [round(r, 4) if r is not None else None for r in _finite(message.ranges)],
    }
