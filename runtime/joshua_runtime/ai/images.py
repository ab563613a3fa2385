"""The one way images change size between a camera and a policy, shared by training and serving.

`joshua-train imitation --image-size WxH` resizes the dataset's frames with `resize` and saves the
policy with that input shape; an INFERENCE node resizes each camera image to the policy's input
shape with the same function, so the policy sees at run time what it saw in training.
"""

import cv2
import numpy as np

# Area averaging: the right filter when shrinking (no aliasing), and exact for integer factors.
INTERPOLATION = cv2.INTER_AREA


def resize(pixels: np.ndarray, width: int, height: int) -> np.ndarray:
    """`pixels` (height x width x channels, uint8 or float) at `width` x `height`; the same array when it fits."""
    if pixels.shape[:2] == (height, width):
        return pixels
    return cv2.resize(pixels, (width, height), interpolation=INTERPOLATION)


def parse_size(text: str) -> tuple[int, int]:
    """(width, height) from `WxH` (e.g. `160x120`); ValueError naming the expected form."""
    parts = text.lower().split("x")
    if len(parts) != 2 or not all(part.isdigit() for part in parts):
        raise ValueError(f"image size {text!r} is not WIDTHxHEIGHT (e.g. 160x120)")
    width, height = int(parts[0]), int(parts[1])
    if width < 1 or height < 1:
        raise ValueError(f"image size {text!r} must be positive")
    return width, height
