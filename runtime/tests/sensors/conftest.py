"""Fixtures of the sensor tests: an in-process rclpy client (see sensor_support; start_node: root conftest)."""

import pytest

from sensor_support import RosClient


@pytest.fixture
def ros_client(ros_domain):
    import rclpy

    context = rclpy.Context()
    rclpy.init(context=context)
    client = RosClient(context)
    yield client
    client.executor.shutdown(timeout_sec=0)
    client.node.destroy_node()
    rclpy.try_shutdown(context=context)
