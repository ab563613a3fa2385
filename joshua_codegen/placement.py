"""Which computer each node and service runs on, when a description declares `host` blocks.

Without hosts every name here is "": one computer, the output as it always was. With hosts, a node or
service block that names no host runs on the first one.
"""

import ipaddress
import re

from joshua_core import control_plane, discovery
from joshua_core.schema import robot_config_pb2 as pb

HOST_NAME = re.compile(r"^[a-z][a-z0-9_]{0,31}$")
# The blocks that add a process besides the nodes, each with its own `host` field.
SERVICE_BLOCKS = ("dashboard", "foxglove", "simulation")
ROS_SYSTEM_SETUP = "/opt/ros/jazzy/setup.sh"  # what a host with ros_from_system sources before Python runs
ROS_SYSTEM_PYTHON = "/usr/bin/python3"  # Debian's interpreter, which apt's ROS packages are built for


def has_hosts(config: pb.RobotConfig) -> bool:
    return len(config.host) > 0


def default_host(config: pb.RobotConfig) -> str:
    """The host of a node or service that names none: the first host ("" without hosts)."""
    return config.host[0].name if config.host else ""


def node_host(config: pb.RobotConfig, node: pb.Node) -> str:
    return node.host or default_host(config)


def service_host(config: pb.RobotConfig, block: str) -> str:
    """The host of the process a service block (SERVICE_BLOCKS) adds."""
    return getattr(config, block).host or default_host(config)


def host_names(config: pb.RobotConfig) -> list[str]:
    return [host.name for host in config.host]


def address_problem(address: str) -> str | None:
    """Why a host's address cannot be used (None when it can): other hosts and DDS locators need an IPv4 address."""
    if not address:
        return "the host has no address; write the IPv4 address the other hosts reach it at"
    try:
        parsed = ipaddress.IPv4Address(address)
    except ValueError:
        return f'address "{address}" is not an IPv4 address (four numbers 0-255, e.g. 10.0.0.2)'
    if parsed.is_unspecified or parsed.is_multicast:
        return f'address "{address}" cannot be reached: write the address of the computer itself'
    return None


def discovery_port(config: pb.RobotConfig) -> int:
    block = config.discovery
    return block.port if block.HasField("port") else discovery.DEFAULT_PORT


def control_host(config: pb.RobotConfig) -> str:
    """The host whose agent the other hosts' agents connect to (`control { host }`, default the first host)."""
    return config.control.host or default_host(config)


def control_port(config: pb.RobotConfig) -> int:
    block = config.control
    return block.port if block.HasField("port") else control_plane.DEFAULT_PORT


def host_python(host: pb.Host) -> str:
    """The interpreter a host's install.sh makes its environment with ("" for the bundle's default)."""
    return host.python or (ROS_SYSTEM_PYTHON if host.ros_from_system else "")
