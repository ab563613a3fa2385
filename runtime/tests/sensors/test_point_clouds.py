"""The lidar path as points: PerceptionPacket point_cloud from the driver, PointCloud2 from the nodes."""

import math

import numpy as np
import pytest
from sensor_msgs.msg import PointCloud2
from sensor_support import SENSOR_QOS, collect, publishers

from joshua_runtime.drivers.lds01 import Lds01Driver
from joshua_runtime.emulators.lds01 import Lds01Emulator
from testsupport.compiled_settings import compiled_node

# Readings of the emulator's room at whole degrees (as test_lds01_driver.py knows them), in metres.
KNOWN = {0: 0.8, 90: 1.5, 270: 1.0}


def cloud_points(message: PointCloud2) -> np.ndarray:
    assert [(f.name, f.offset, f.datatype) for f in message.fields] == [
        ("x", 0, 7),
        ("y", 4, 7),
        ("z", 8, 7),
        ("intensity", 12, 7),
    ]
    assert (message.height, message.point_step, message.is_bigendian) == (1, 16, False)
    return np.frombuffer(bytes(message.data), dtype="<f4").reshape(message.width, 4)


def near(points: np.ndarray, x: float, y: float) -> bool:
    return bool(np.any(np.hypot(points[:, 0] - x, points[:, 1] - y) < 1e-3))


def test_driver_packets_hold_the_valid_readings_as_points(tmp_path):
    port = str(tmp_path / "ttyLDS")
    with Lds01Emulator(port), Lds01Driver(port, frame_id="laser") as lidar:
        packet = lidar.read_scan()
    sensor = packet.sensor
    valid = [i for i, r in enumerate(sensor.ranges) if sensor.range_min <= r <= sensor.range_max]
    points = np.array(packet.point_cloud.xyz).reshape(-1, 3)
    assert len(points) == len(valid) == len(packet.point_cloud.intensity) and 0 < len(valid) < 360
    for degree, metres in KNOWN.items():
        angle = sensor.angle_min + degree * sensor.angle_increment
        assert near(points, metres * math.cos(angle), metres * math.sin(angle)), degree
    assert np.all(points[:, 2] == 0.0)
    assert list(packet.point_cloud.intensity) == [sensor.intensities[i] for i in valid]


def test_a_lidar_node_with_point_cloud_type_publishes_point_clouds(tmp_path, start_node, ros_client):
    link = tmp_path / "ttyLIDAR"
    with Lds01Emulator(link):
        node = start_node(
            compiled_node(
                f'name: "lidar" type: LIDAR_PUBLISHER topic_name: "/points" message_type: "sensor_msgs/msg/PointCloud2" '
                f'serial_port: "{link}" baud_rate: 230400 rate_hz: 5 frame_id: "laser"'
            )
        )
        assert [i.topic_type for i in publishers(ros_client, "/points", node)] == ["sensor_msgs/msg/PointCloud2"]
        [cloud] = collect(ros_client, PointCloud2, "/points", SENSOR_QOS, 1)
    assert cloud.header.frame_id == "laser"
    points = cloud_points(cloud)
    assert 0 < len(points) < 360
    step = 2 * math.pi / 360
    for degree, metres in KNOWN.items():
        assert near(points, metres * math.cos(degree * step), metres * math.sin(degree * step)), degree


def test_a_mock_lidar_publishes_point_clouds_too(start_node, ros_client):
    node = start_node(
        compiled_node(
            'name: "lidar" type: MOCK_LIDAR_PUBLISHER topic_name: "/points" message_type: "sensor_msgs/msg/PointCloud2"'
        )
    )
    [cloud] = collect(ros_client, PointCloud2, "/points", SENSOR_QOS, 1)
    assert len(cloud_points(cloud)) > 100, node.failure()
    assert cloud.header.frame_id == "laser"


@pytest.mark.parametrize("message_type", ["sensor_msgs/msg/PointCloud2"])
def test_the_compiler_accepts_point_clouds_for_lidars(message_type):
    settings = compiled_node(f'type: MOCK_LIDAR_PUBLISHER topic_name: "/p" message_type: "{message_type}"')
    assert settings["topic"]["message_type"] == message_type
