"""The message catalogue lists exactly the messages of the installed ROS 2 Jazzy packages."""

import importlib

from joshua_codegen import msg_catalog

INSTALLED = (
    "std_msgs",
    "sensor_msgs",
    "geometry_msgs",
    "nav_msgs",
    "trajectory_msgs",
    "tf2_msgs",
)  # tf2_msgs: built by set-up


def test_catalogue_matches_the_installed_message_packages():
    for package in INSTALLED:
        module = importlib.import_module(f"{package}.msg")
        installed = {name for name in dir(module) if name[:1].isupper()}
        assert set(msg_catalog.PACKAGES[package]) == installed, package
    assert len(msg_catalog.MESSAGE_TYPES) == sum(len(names) for names in msg_catalog.PACKAGES.values())


def test_near_misses_get_the_intended_type():
    assert msg_catalog.closest("sensor_msgs/Image") == "sensor_msgs/msg/Image"
    assert msg_catalog.closest("sensor_msgs::msg::JointState") == "sensor_msgs/msg/JointState"
    assert msg_catalog.closest("sensor_msgs/msg/laserscan") == "sensor_msgs/msg/LaserScan"
    assert msg_catalog.closest("tf2_msgs/msg/TFMesage") == "tf2_msgs/msg/TFMessage"
    assert msg_catalog.closest("my_msgs/msg/Thing") is None
    assert msg_catalog.is_well_formed("my_msgs/msg/Thing")
    assert not msg_catalog.is_well_formed("sensor_msgs/Image")
