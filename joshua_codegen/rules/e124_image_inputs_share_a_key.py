"""E124 image-inputs-share-a-key: two image inputs of one node become the same dataset feature.

What it checks:
    The image `input_topics` of one INFERENCE or DATA_SUBSCRIBER node (those published as
    sensor_msgs/msg/Image or CompressedImage in the description) map to different LeRobot features
    `observation.images.<key>`. The key is the topic without a last segment starting with `image`,
    its segments joined by `_`: `/front/image_raw` and `/front/image_rect` both become `front`.

Why it matters:
    The recorder and the policy refuse to start: the two cameras would overwrite each other.

Example:
    node {
      type: DATA_SUBSCRIBER
      input_topics: ["/front/image_raw", "/front/image_rect"]   # error: both become observation.images.front
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.feature_keys import image_feature
from joshua_core.message_types import IMAGE_TYPES

CODE = "E124"
NAME = "image-inputs-share-a-key"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    first_by_node: dict[tuple[int, str], object] = {}
    for topic, readers in ctx.readers.items():
        published = [p.message_type for p in ctx.publishers.get(topic, ()) if p.message_type]
        if not published or published[0] not in IMAGE_TYPES:
            continue
        for reader in readers:
            feature = image_feature(topic)
            first = first_by_node.setdefault((reader.view.index, feature), reader)
            if first is not reader and first.topic != topic:
                yield Finding(
                    reader.at,
                    f'"{topic}" and "{first.topic}" both become the feature {feature} '
                    f"of {reader.view.label}; rename one of the camera topics",
                    ((first.at, "other input listed here"),),
                )
