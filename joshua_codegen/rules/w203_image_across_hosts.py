"""W203 image-across-hosts: raw images cross from one host to another.

What it checks:
    With `host { }` blocks, a sensor_msgs/msg/Image topic whose publisher and a subscriber run on
    different hosts, after the build moved every reader it could onto the camera's JPEG copy
    `<topic>/compressed` (readers that take CompressedImage: {compressed_readers_types}, a recorder
    writing an mcap bag excepted). What is left: CUSTOM publishers and subscribers, bag recorders,
    cameras the simulation stands in for. The warning gives the stream's bandwidth when the publisher
    is a camera (width x height x 3 bytes x rate_hz).

Why it matters:
    A 640x480 camera at 30 Hz sends 27.6 MB/s of raw pixels: more than Wi-Fi carries, and a large
    share of a wired 1 Gbit/s link; on one host they go through shared memory, between hosts over UDP.

Example:
    robot_config {
      host { name: "arm" address: "10.0.0.2" }
      host { name: "gpu" address: "10.0.0.3" }
      node { type: CAMERA_PUBLISHER topic_name: "/camera/image_raw" }
      node { name: "viewer" type: CUSTOM host: "gpu" executable: "/usr/bin/viewer"
             subscribes { topic_name: "/camera/image_raw" message_type: "sensor_msgs/msg/Image" } }
      # warning: /camera/image_raw carries raw images from host "arm" to host "gpu" (27.6 MB/s) ...
    }
"""

from joshua_codegen import image_transport
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding

TYPE_LISTS = {
    "compressed_readers_types": lambda entry: image_transport.COMPRESSED_IMAGE in entry.input_types,
}
CODE = "W203"
NAME = "image-across-hosts"
SEVERITY = WARNING
STAGE = "plan"


def check(ctx):
    robot = ctx.robot
    if not robot.hosts:
        return
    hosts = {node.name: node.host for node in robot.nodes}
    views = {view.name: view for view in ctx.nodes}
    for topic in robot.topics:
        if topic.message_type != image_transport.IMAGE:
            continue
        for publisher in topic.publishers:
            source = hosts[publisher.node]
            rate = image_transport.bandwidth_mb_s(views[publisher.node].node)
            figure = f" ({rate:.1f} MB/s)" if rate is not None else ""
            for subscriber in topic.subscribers:
                if hosts[subscriber.node] == source:
                    continue
                declared = ctx.subscribers.get(topic.name, []) + ctx.readers.get(topic.name, [])
                at = next((e.at for e in declared if e.view.name == subscriber.node), views[subscriber.node].path)
                yield Finding(
                    at,
                    f'{topic.name} carries raw images from host "{source}" to host "{hosts[subscriber.node]}"'
                    f"{figure}; publish sensor_msgs/msg/CompressedImage (message_type) or read it on the "
                    "camera's host",
                    ((ctx.publishers[topic.name][0].at, "published here"),) if ctx.publishers.get(topic.name) else (),
                )
