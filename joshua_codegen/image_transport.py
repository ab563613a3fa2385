"""Images between hosts: a camera whose Image topic is read on another host also publishes it as JPEG.

As image_transport does, the copy is `<topic>/compressed` (sensor_msgs/msg/CompressedImage, the same QoS),
and every reader on another host that takes CompressedImage (its registry entry's input_types; a
recorder writing a bag excepted, since a bag keeps topics as they are) is planned onto it; readers on the
camera's own host keep the raw Image over shared memory. A policy or dataset names the image after the
topic without the `compressed` segment (joshua_core.feature_keys), so nothing else changes. Where no such
switch is possible (a CUSTOM publisher or subscriber, a bag recorder, a simulated camera), an Image
crossing hosts stays raw, and W203 warns with its bandwidth.
"""

from dataclasses import replace

from joshua_codegen import defaults, placement, topology
from joshua_codegen.positions import node_path
from joshua_core.feature_keys import COMPRESSED_SEGMENT
from joshua_core.message_types import IMAGE_TYPES
from joshua_core.models import BAG_FORMAT
from joshua_core.node_families import Family
from joshua_core.schema import robot_config_pb2 as pb

IMAGE, COMPRESSED_IMAGE = IMAGE_TYPES
COMPRESSED_FIELD = "compressed_topic"  # the settings field of a camera's JPEG copy (NodeSettings.compressed_topic)
BYTES_PER_PIXEL = 3  # bgr8 / rgb8, what the camera nodes publish
MEGABYTE = 1_000_000


def compressed_name(topic: str) -> str:
    return f"{topic.rstrip('/')}/{COMPRESSED_SEGMENT}"


def takes_compressed(node: pb.Node) -> bool:
    """The node reads CompressedImage as well as Image on its inputs, under the same feature name."""
    entry = defaults.entry(node)
    if COMPRESSED_IMAGE not in entry.input_types:
        return False
    return not (entry.family == Family.RECORDER and defaults.output_format(node) == BAG_FORMAT)


def sends_compressed(config: pb.RobotConfig, node: pb.Node) -> bool:
    """The node runs as a camera process of its own (not simulated) that can publish a JPEG copy."""
    simulated = config.mode == pb.MODE_SIMULATION and node.type in defaults.HARDWARE
    return defaults.entry(node).family == Family.CAMERA and not simulated


def across_hosts(config: pb.RobotConfig, declared: list[topology.Declaration]) -> list[topology.Declaration]:
    """`declared` with the readers of a camera's Image topic on other hosts moved onto `<topic>/compressed`,
    and that topic added to the camera's publications (as its `compressed_topic`). Unchanged without hosts."""
    if not placement.has_hosts(config):
        return declared
    hosts = [placement.node_host(config, node) for node in config.node]
    publishers: dict[str, list[topology.Declaration]] = {}
    for item in declared:
        if item.role == topology.PUBLISHER:
            publishers.setdefault(item.topic, []).append(item)
    cameras = {
        topic: items[0]
        for topic, items in publishers.items()
        if len(items) == 1
        and items[0].message_type == IMAGE
        and items[0].at[-1] == "topic_name"
        and sends_compressed(config, config.node[items[0].index])
    }
    switched, copies = [], {}
    for item in declared:
        camera = cameras.get(item.topic) if item.role == topology.READER else None
        if camera is None or hosts[item.index] == hosts[camera.index] or not takes_compressed(config.node[item.index]):
            switched.append(item)
            continue
        switched.append(replace(item, topic=compressed_name(item.topic)))
        copies[camera.topic] = replace(
            camera,
            topic=compressed_name(camera.topic),
            message_type=COMPRESSED_IMAGE,
            at=node_path(camera.index) + (COMPRESSED_FIELD,),
        )
    return switched + [copies[topic] for topic in sorted(copies)]


def bandwidth_mb_s(node: pb.Node) -> float | None:
    """MB/s of a camera node's raw images at its size and rate; None for a node that is no camera."""
    if defaults.entry(node).family != Family.CAMERA:
        return None
    return defaults.width(node) * defaults.height(node) * BYTES_PER_PIXEL * defaults.rate_hz(node) / MEGABYTE
