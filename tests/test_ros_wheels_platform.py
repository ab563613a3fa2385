"""The platform install.sh demands of a host that takes the ROS 2 wheels is the one the runtime's dependencies
name for them: Python 3.11 on x86_64 (runtime/pyproject.toml), stated once more in joshua_codegen/bundle.py."""

import tomllib

from packaging.markers import default_environment
from packaging.requirements import Requirement

from joshua_codegen.bundle import ROS_WHEEL_PREFIX, ROS_WHEELS_MACHINE, ROS_WHEELS_PYTHON
from testsupport.joshuac_cli import ROOT

PLATFORMS = [(python, machine) for python in ("3.10", "3.11", "3.12") for machine in ("x86_64", "aarch64")]


def ros_requirements() -> list[Requirement]:
    project = tomllib.loads((ROOT / "runtime" / "pyproject.toml").read_text())["project"]
    return [r for r in map(Requirement, project["dependencies"]) if r.name.startswith(ROS_WHEEL_PREFIX)]


def test_the_runtime_takes_the_ros_wheels_exactly_where_install_sh_demands_them():
    requirements = ros_requirements()
    assert {r.name for r in requirements} >= {"ros-jazzy-rclpy", "ros-jazzy-sensor-msgs"}
    for python, machine in PLATFORMS:
        environment = {**default_environment(), "python_version": python, "platform_machine": machine}
        expected = (python, machine) == (ROS_WHEELS_PYTHON, ROS_WHEELS_MACHINE)
        assert [r.name for r in requirements if r.marker.evaluate(environment) != expected] == [], (python, machine)
