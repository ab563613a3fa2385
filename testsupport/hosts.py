"""Simulated computers for tests: each a network namespace with its own /dev/shm, all wired to one switch.

    with virtual_hosts("robot", "gpu") as hosts:
        talker = hosts["robot"].popen([...], env=env)      # runs inside host "robot"
        hosts["gpu"].link_down(); ...; hosts["gpu"].link_up()
        hosts.block_multicast()                            # a network without multicast

Each host is a network namespace (loopback up, `eth0` with ADDRESS_PREFIX.<i+1>/24 and a default route
on it) plus a persistent mount namespace whose /dev/shm is a tmpfs of its own, so Fast DDS shared
memory stays inside one host as it does between real computers. Every process of a host enters both
namespaces (`nsenter --net --mount`, which execs in place: the Popen's pid is the program's). The hosts'
`eth0` are veth pairs whose other ends are ports of a bridge inside a "switch" namespace; a host's link
goes down and up at its switch port, as when its cable is pulled. Addresses are private and exist only
inside the namespaces; the machine's own network is never touched.

Names are unique per process and set (parallel test workers each make their own); leaving the block
kills every process of the hosts, deletes the namespaces and unmounts the mount namespaces, also when
the block raised. A set left behind by a process that died is removed when the next set is made
(stale_hosts.py). Needs root.
"""

import itertools
import os
import re
import signal
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from testsupport import host_namespaces as ns
from testsupport import netem, stale_hosts

ADDRESS_PREFIX = "10.201.0"  # host i is ADDRESS_PREFIX.(i + 1)
PREFIX_LENGTH = 24
HOST_INTERFACE = "eth0"
BRIDGE = "br0"
SWITCH = "switch"
HOST_NAME = re.compile(r"^[a-z][a-z0-9]{0,11}$")  # part of namespace and port names
PROCESS_EXIT_TIMEOUT_S = 10.0  # a killed process is reaped within this
RUN_TIMEOUT_S = 60.0  # Host.run's default

_set_numbers = itertools.count(1)


class Host:
    """One simulated computer: processes started inside it, its link, its counters."""

    def __init__(self, name: str, address: str, network: "HostNetwork"):
        self.name, self.address, self.network = name, address, network
        self.netns = f"{network.set_name}-{name}"
        self.mount_namespace = network.state_dir / f"{name}.mnt"
        self.port = f"port-{name}"
        self.processes: list[subprocess.Popen] = []

    def command(self, args: list[str], cwd: str | os.PathLike | None = None) -> list[str]:
        """`args` as run inside this host (nsenter into its network and mount namespaces, working in `cwd`)."""
        workdir = os.fspath(cwd) if cwd is not None else os.getcwd()
        return [
            "nsenter", f"--net={ns.NETNS_DIR / self.netns}", f"--mount={self.mount_namespace}", f"--wd={workdir}",
            "--", *map(os.fspath, args),
        ]  # fmt: skip

    def popen(self, args: list[str], cwd=None, **popen_args) -> subprocess.Popen:
        """Start a process inside this host (subprocess.Popen arguments); killed when the set closes."""
        process = subprocess.Popen(self.command(args, cwd), **popen_args)
        self.processes.append(process)
        return process

    def run(self, args: list[str], cwd=None, timeout: float = RUN_TIMEOUT_S, **run_args) -> subprocess.CompletedProcess:
        """Run a command inside this host to its end (subprocess.run arguments)."""
        return subprocess.run(self.command(args, cwd), timeout=timeout, **run_args)

    def link_down(self) -> None:
        """Take this host off the switch (its port goes down: no frame in or out, as with a pulled cable)."""
        ns.set_link(self.network.switch, self.port, up=False)

    def link_up(self) -> None:
        ns.set_link(self.network.switch, self.port, up=True)

    def counters(self, interface: str = HOST_INTERFACE) -> dict[str, int]:
        """Bytes and packets through an interface of this host so far (rx_bytes, tx_bytes, rx_packets, tx_packets)."""
        return ns.interface_counters(self.netns, interface)

    def shm_files(self) -> list[str]:
        """Names of the files in this host's /dev/shm."""
        result = self.run(["ls", "-1", "/dev/shm"], capture_output=True, text=True, check=True)
        return result.stdout.split()

    def impair(self, delay_ms: float = 0.0, loss_percent: float = 0.0) -> None:
        """Delay and drop this host's outgoing packets (netem); NetemUnavailable when the kernel lacks it."""
        netem.impair(self.network.switch, self.netns, HOST_INTERFACE, delay_ms, loss_percent)

    def kill_processes(self) -> None:
        """SIGKILL and reap the processes started here, then any process still in the host's namespace (and remove
        the cgroups of the robots' supervisors among them)."""
        for process in self.processes:
            if process.poll() is None:
                process.send_signal(signal.SIGKILL)
            try:
                process.wait(PROCESS_EXIT_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                pass
        stale_hosts.kill_namespace_processes(self.netns)
        stale_hosts.remove_supervisor_cgroups({process.pid for process in self.processes})


class HostNetwork:
    """A set of hosts on one switch; `network[name]` is a Host."""

    def __init__(self, names: tuple[str, ...]):
        bad = [name for name in names if not HOST_NAME.match(name)]
        if bad or len(set(names)) != len(names) or not names:
            raise ValueError(f"host names must be distinct and match {HOST_NAME.pattern}: {names}")
        self.set_name = f"{stale_hosts.SET_PREFIX}{os.getpid()}x{next(_set_numbers)}"
        self.state_dir: Path = ns.STATE_ROOT / self.set_name
        self.switch = f"{self.set_name}-{SWITCH}"
        self.hosts = {name: Host(name, f"{ADDRESS_PREFIX}.{index + 1}", self) for index, name in enumerate(names)}

    def __getitem__(self, name: str) -> Host:
        return self.hosts[name]

    def __iter__(self) -> Iterator[Host]:
        return iter(self.hosts.values())

    def create(self) -> None:
        ns.create_state_dir(self.state_dir)
        stale_hosts.write_owner(self.state_dir)
        ns.create_network_namespace(self.switch)
        ns.create_bridge(self.switch, BRIDGE)
        for host in self:
            ns.create_network_namespace(host.netns)
            ns.create_mount_namespace(host.mount_namespace)
            ns.connect(self.switch, BRIDGE, host.port, host.netns, HOST_INTERFACE, f"{host.address}/{PREFIX_LENGTH}")

    def block_multicast(self, blocked: bool = True) -> None:
        """Make the switch drop multicast (as many Wi-Fi and cloud networks do); unicast and broadcast still pass."""
        for host in self:
            ns.set_multicast_flood(self.switch, host.port, flood=not blocked)

    def close(self) -> None:
        """Kill every process of the hosts, then delete the namespaces and the set's directory."""
        errors = []
        for host in self:
            try:
                host.kill_processes()
            except (ns.HostSetupError, OSError) as exc:
                errors.append(exc)
        stale_hosts.remove_set(self.set_name)
        if errors:
            raise ns.HostSetupError(f"closing hosts {self.set_name}: {'; '.join(map(str, errors))}")


@contextmanager
def virtual_hosts(*names: str) -> Iterator[HostNetwork]:
    """Hosts named `names` on one switch, for the duration of the block (see the module's docstring)."""
    stale_hosts.remove_stale_sets()
    network = HostNetwork(names)
    try:
        network.create()
        yield network
    finally:
        network.close()
