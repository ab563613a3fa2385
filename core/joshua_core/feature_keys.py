"""LeRobot feature keys of image topics: both the recorder and the compiler's checks derive them here.

An Image (or CompressedImage) input becomes `observation.images.<key>`, where `<key>` is the topic name
without its leading slash, without a last segment `compressed` (image_transport's name for the JPEG
copy of an image topic, which is the same camera) and then without a last segment starting with `image`
(`image_raw`, `image_rect`, ...), the remaining segments joined by `_`:
`/camera/image_raw` -> `camera`, `/camera/image_raw/compressed` -> `camera`, `/arm/wrist/image` ->
`arm_wrist`, `/front` -> `front`.
"""

import re

IMAGE_PREFIX = "observation.images."
COMPRESSED_SEGMENT = "compressed"

_NOT_KEY_CHARACTER = re.compile(r"[^A-Za-z0-9_]")


def image_key(topic_name: str) -> str:
    """The `<key>` of `observation.images.<key>` for an Image topic (see the module docstring)."""
    parts = [part for part in topic_name.split("/") if part]
    if len(parts) > 1 and parts[-1] == COMPRESSED_SEGMENT:
        parts = parts[:-1]
    if len(parts) > 1 and parts[-1].startswith("image"):
        parts = parts[:-1]
    key = _NOT_KEY_CHARACTER.sub("_", "_".join(parts))
    return key or "image"


def image_feature(topic_name: str) -> str:
    """`observation.images.<key>` for an Image topic."""
    return IMAGE_PREFIX + image_key(topic_name)
