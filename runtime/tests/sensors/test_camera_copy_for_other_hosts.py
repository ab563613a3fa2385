"""A camera whose images a policy on another host reads publishes a JPEG copy on `<topic>/compressed` as well.

The settings come from the compiler: a two-host description with the camera on one host and the
policy on the other; the node runs as a real process and an in-process rclpy client reads both topics.
"""

import cv2
import numpy as np
from sensor_msgs.msg import CompressedImage, Image
from sensor_support import SENSOR_QOS, collect, publishers

from joshua_runtime.nodes.mock_camera_publisher import gradient
from testsupport.compiled_settings import compiled_settings

WIDTH, HEIGHT = 160, 120
JPEG_TOLERANCE = 4  # mean absolute difference of a JPEG-decoded frame from the raw one
TWO_HOSTS = f"""
robot_config {{
  name: "test_robot"
  mode: MODE_INFERENCE
  host {{ name: "arm" address: "10.0.0.2" }}
  host {{ name: "gpu" address: "10.0.0.3" }}
  node {{ name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/cam/image_raw" width: {WIDTH} height: {HEIGHT} rate_hz: 20 }}
  node {{ name: "policy" type: INFERENCE host: "gpu" topic_name: "/arm/commands"
          input_topics: ["/cam/image_raw"] model_path: "/models/act" }}
}}
"""


def test_the_camera_publishes_raw_images_and_their_jpeg_copy(start_node, ros_client):
    settings = compiled_settings(TWO_HOSTS)
    camera = settings["cam"]
    assert camera["compressed_topic"]["name"] == "/cam/image_raw/compressed"
    assert [i["name"] for i in settings["policy"]["inputs"]] == ["/cam/image_raw/compressed"]
    node = start_node(camera)
    assert [i.topic_type for i in publishers(ros_client, "/cam/image_raw/compressed", node)] == [
        "sensor_msgs/msg/CompressedImage"
    ]
    (raw,) = collect(ros_client, Image, "/cam/image_raw", SENSOR_QOS, 1)
    (copy,) = collect(ros_client, CompressedImage, "/cam/image_raw/compressed", SENSOR_QOS, 1)
    assert (raw.width, raw.height) == (WIDTH, HEIGHT)
    assert copy.format == "jpeg" and copy.header.frame_id == raw.header.frame_id
    frame = cv2.imdecode(np.frombuffer(bytes(copy.data), np.uint8), cv2.IMREAD_COLOR)
    assert frame.shape == (HEIGHT, WIDTH, 3)
    base = gradient(WIDTH, HEIGHT)
    # the pattern scrolls horizontally only: every column holds one of the base frame's columns
    assert np.abs(frame[:, :, 1].astype(int) - base[:, :, 1].astype(int)).mean() < JPEG_TOLERANCE
