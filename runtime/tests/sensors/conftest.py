"""Fixtures of the sensor tests: node processes and an in-process rclpy client (see sensor_support)."""

import pytest

from sensor_support import NodeProcess, RosClient


@pytest.fixture
def start_node(ros_env):
    """Start node processes in the test's ROS domain; kill the ones still running at the end."""
    started = []

    def start(settings: dict, **extra_env) -> NodeProcess:
        node = NodeProcess(settings, dict(ros_env, **extra_env))
        started.append(node)
        return node

    yield start
    for node in started:
        node.kill()


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
