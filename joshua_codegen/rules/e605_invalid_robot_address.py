"""E605 invalid-robot-address: a fleet robot's address, SSH user or SSH port cannot be used.

What it checks:
    A robot's `address` is an IP address or a host name (letters, digits and hyphens, dot-separated),
    and is not given for a robot whose description has `host` blocks (each host has its own),
    `ssh_user` a user name (lower-case letters, digits, `_` and `-`, starting with a letter or `_`),
    `ssh_port` within 1-65535.

Why it matters:
    The rollout reaches each robot over SSH at this address as this user; anything else (a URL, a
    `user@host`, a space) would fail only during a rollout, robot after robot.

Example:
    robot { name: "arm_1" address: "ssh://10.0.0.11" ... }   # error: not an IP address or host name
"""

import ipaddress
import re

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.fleet.load import robot_path
from joshua_codegen.rules.context import Finding

CODE = "E605"
NAME = "invalid-robot-address"
SEVERITY = ERROR
STAGE = "fleet"
MAX_HOST_NAME_CHARS = 253
_LABEL = re.compile(r"^(?!-)[A-Za-z0-9-]{1,63}(?<!-)$")
_USER = re.compile(r"^[a-z_][a-z0-9_-]{0,31}$")
MAX_PORT = 65535


def is_address(text: str) -> bool:
    try:
        ipaddress.ip_address(text)
        return True
    except ValueError:
        pass
    labels = text.removesuffix(".").split(".")
    return len(text) <= MAX_HOST_NAME_CHARS and all(_LABEL.match(label) for label in labels)


def check(ctx):
    for member in ctx.members:
        index, robot = member.index, member.entry
        if robot.address and member.config is not None and member.config.host:
            hosts = ", ".join(host.name for host in member.config.host)
            yield Finding(
                robot_path(index, "address"),
                f"robot {robot.name} runs on the hosts of its description ({hosts}): give their addresses in "
                'host { name: "..." address: "..." } blocks; address is for a robot on one computer',
            )
        elif robot.address and not is_address(robot.address):
            yield Finding(
                robot_path(index, "address"),
                f'address "{robot.address}" is not an IP address or a host name (e.g. 10.0.0.11 or arm-1.lab); '
                "give the user in ssh_user and the port in ssh_port",
            )
        if robot.ssh_user and not _USER.match(robot.ssh_user):
            yield Finding(
                robot_path(index, "ssh_user"),
                f'ssh_user "{robot.ssh_user}" is not a user name (lower-case letters, digits, "_" and "-")',
            )
        if robot.HasField("ssh_port") and not 1 <= robot.ssh_port <= MAX_PORT:
            yield Finding(robot_path(index, "ssh_port"), f"ssh_port {robot.ssh_port} is out of range 1-{MAX_PORT}")
