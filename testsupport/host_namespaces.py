"""The kernel side of simulated computers: network namespaces, persistent mount namespaces, veth pairs.

Everything here runs `ip`, `mount`, `umount` and `unshare` as root and touches only what it names: a
network namespace `/run/netns/<name>`, and the set's own directory under STATE_ROOT (a private tmpfs
holding the files that keep each host's mount namespace alive). Nothing is added to the machine's own
network: every interface is created inside a namespace of the set.
"""

import contextlib
import json
import os
import subprocess
from pathlib import Path

STATE_ROOT = Path("/run/joshua-test-hosts")  # one directory per set of hosts: owner record, mount namespaces
NETNS_DIR = Path("/run/netns")  # where `ip netns add` keeps its namespaces
COMMAND_TIMEOUT_S = 20.0  # one ip/mount/tc command on a busy machine
SHM_SIZE = "512m"  # each host's /dev/shm (Fast DDS: 16 MiB image segments per participant and its port files)
STATE_DIR_SIZE = "1m"  # the set directory only holds small files and mount points


class HostSetupError(RuntimeError):
    """A namespace command failed; the message names the command and what it printed."""


def run(*command: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run one command; HostSetupError with its output when it fails and `check` is set."""
    result = subprocess.run(command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if check and result.returncode != 0:
        raise HostSetupError(f"`{' '.join(command)}` failed ({result.returncode}): {result.stderr.strip()}")
    return result


def create_state_dir(path: Path) -> None:
    """The set's directory, on a private tmpfs of its own (persistent mount namespaces need a private mount)."""
    path.mkdir(parents=True)
    run("mount", "-t", "tmpfs", "-o", f"size={STATE_DIR_SIZE},mode=0700", "joshua-test-hosts", str(path))
    run("mount", "--make-private", str(path))


def remove_state_dir(path: Path) -> None:
    """Unmount the set's mount namespace files and its tmpfs, then remove the directory (absent parts skipped:
    two test workers making sets at once may both remove the same stale set)."""
    if path.is_dir() and os.path.ismount(path):
        for namespace_file in sorted(path.glob("*.mnt")):
            if os.path.ismount(namespace_file):
                run("umount", str(namespace_file), check=False)
        run("umount", "--lazy", str(path), check=False)
    with contextlib.suppress(FileNotFoundError):
        for leftover in path.iterdir():
            leftover.unlink(missing_ok=True)
        path.rmdir()


def create_mount_namespace(namespace_file: Path) -> None:
    """A mount namespace kept alive by `namespace_file`, with a private tmpfs on /dev/shm.

    Mounts the machine makes later still appear inside (slave propagation); the tmpfs never leaves it.
    """
    namespace_file.touch()
    run(
        "unshare", f"--mount={namespace_file}", "--propagation", "slave", "--",
        "mount", "-t", "tmpfs", "-o", f"size={SHM_SIZE},mode=1777", "joshua-host-shm", "/dev/shm",
    )  # fmt: skip


def create_network_namespace(name: str) -> None:
    run("ip", "netns", "add", name)
    run("ip", "-n", name, "link", "set", "lo", "up")


def delete_network_namespace(name: str) -> None:
    if (NETNS_DIR / name).exists():
        run("ip", "netns", "delete", name, check=False)


def network_namespace_pids(name: str) -> list[int]:
    """The processes whose network namespace is `name` (empty when it does not exist)."""
    if not (NETNS_DIR / name).exists():
        return []
    result = run("ip", "netns", "pids", name, check=False)
    return [int(pid) for pid in result.stdout.split()]


def network_namespaces() -> list[str]:
    """Names of every namespace `ip netns` knows."""
    return sorted(entry.name for entry in NETNS_DIR.iterdir()) if NETNS_DIR.is_dir() else []


def create_bridge(switch: str, bridge: str) -> None:
    """A bridge inside the switch namespace; IGMP snooping off, so multicast reaches every port as on a hub."""
    run("ip", "-n", switch, "link", "add", bridge, "type", "bridge", "mcast_snooping", "0")
    run("ip", "-n", switch, "link", "set", bridge, "up")


def connect(switch: str, bridge: str, port: str, host: str, interface: str, address_cidr: str) -> None:
    """A veth pair: `port` on the switch's bridge, `interface` in `host` with the address and a default route."""
    run("ip", "-n", switch, "link", "add", port, "type", "veth", "peer", "name", interface, "netns", host)
    run("ip", "-n", switch, "link", "set", port, "master", bridge)
    run("ip", "-n", switch, "link", "set", port, "up")
    run("ip", "-n", host, "addr", "add", address_cidr, "dev", interface)
    run("ip", "-n", host, "link", "set", interface, "up")
    run("ip", "-n", host, "route", "add", "default", "dev", interface)


def set_multicast_flood(switch: str, port: str, flood: bool) -> None:
    """Whether the bridge floods multicast frames out of `port` (IGMP snooping is off: all multicast floods)."""
    run("bridge", "-n", switch, "link", "set", "dev", port, "mcast_flood", "on" if flood else "off")


def set_link(namespace: str, interface: str, up: bool) -> None:
    run("ip", "-n", namespace, "link", "set", interface, "up" if up else "down")


def interface_counters(namespace: str, interface: str) -> dict[str, int]:
    """rx/tx bytes and packets of an interface inside a namespace (from its sysfs statistics via `ip -s`)."""
    result = run("ip", "-n", namespace, "-s", "-j", "link", "show", "dev", interface)
    stats = json.loads(result.stdout)[0]["stats64"]
    return {
        "rx_bytes": stats["rx"]["bytes"],
        "rx_packets": stats["rx"]["packets"],
        "tx_bytes": stats["tx"]["bytes"],
        "tx_packets": stats["tx"]["packets"],
    }
