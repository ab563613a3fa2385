"""Fixtures of the multi-host tests: two simulated computers and the ROS environment of their processes."""

import pytest

from testsupport.hosts import virtual_hosts


@pytest.fixture
def hosts():
    """Hosts "robot" (10.201.0.1) and "gpu" (10.201.0.2) on one switch, removed after the test."""
    with virtual_hosts("robot", "gpu") as network:
        yield network


@pytest.fixture
def subnet_env(ros_env) -> dict:
    """The test's ROS environment with discovery over the subnet: inside the hosts' namespaces, the
    subnet is the test's own switch, so nothing leaves it."""
    return dict(ros_env, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET")
