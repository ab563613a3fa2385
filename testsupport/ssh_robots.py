"""Robots reachable over SSH for fleet tests: simulated computers (hosts.py) each running Debian's sshd.

    with ssh_robots(tmp_path, ["arm1", "arm2"]) as fleet:
        fleet.robots["arm1"].address                       # 10.201.0.2: only inside the namespaces
        fleet.deploy(["deploy", str(out), "--canary", "1"])  # joshua-fleet run on the "deployer" host
        fleet.robots["arm1"].run(["cat", "/opt/joshua/current/manifest.json"])

Every robot is a network namespace plus a mount namespace of its own, in which /opt (the real release root
/opt/joshua lives there), /run and /var/log are private tmpfs mounts: releases, pid files, sshd's privilege
separation directory and login records stay inside the robot. Its sshd (`/usr/sbin/sshd -D -f CONFIG`)
listens on the robot's address only, with a host key and authorized key made for the test in `directory`;
root logs in with that key. The deployer is one more host on the same switch, where `joshua-fleet` runs
Ansible with the test's private key, known_hosts and Ansible directories, and SSH connection sharing of its
own (CONTROL_DIR_PREFIX): fleets of tests running at once never share a connection. Leaving the block kills
every process of the hosts (sshd, supervisors, nodes) and deletes the namespaces (hosts.py).
"""

import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from testsupport.hosts import Host, HostNetwork, virtual_hosts

DEPLOYER = "deployer"
PRIVATE_MOUNTS = {"/opt": "size=512m,mode=0755", "/run": "size=16m,mode=0755", "/var/log": "size=16m,mode=0755"}
SSHD_READY_TIMEOUT_S = 20.0
SSHD_POLL_S = 0.1
DEPLOY_TIMEOUT_S = 900.0  # a rollout of a few robots on a busy machine
VENV_BIN = Path(sys.executable).parent
# The deployer's SSH connection sharing (Ansible's ControlPersist masters) keeps its sockets here, one directory
# per fleet: by default they are in ~/.ansible/cp, named after address, port and user alone, so that the
# deployers of two fleets at once (the same addresses, each on its own switch) would use each other's masters
# and run their commands on the other fleet's robots. In /tmp, not the test directory: a socket's path must
# stay under 108 bytes (sun_path), and ssh adds 17 to it while it makes one.
CONTROL_DIR_PREFIX = "ssh-control-"


@dataclass
class SshRobot:
    host: Host
    sshd: subprocess.Popen | None = None

    @property
    def address(self) -> str:
        return self.host.address

    def run(self, args: list[str], **run_args) -> subprocess.CompletedProcess:
        """Run a command inside the robot (its network and mount namespaces), text output captured."""
        return self.host.run(args, capture_output=True, text=True, **run_args)

    def write(self, path: str, data: bytes, mode: int = 0o644) -> None:
        """Write a file inside the robot's own file system view (its private /opt, say)."""
        command = f"mkdir -p \"$(dirname '{path}')\" && cat > '{path}' && chmod {mode:o} '{path}'"
        self.host.run(["sh", "-c", command], input=data, check=True, capture_output=True)


class SshFleet:
    def __init__(self, network: HostNetwork, directory: Path, names: list[str], control_dir: Path):
        self.network = network
        self.directory = directory
        self.control_dir = control_dir
        self.robots = {name: SshRobot(network[name]) for name in names}
        self.deployer = network[DEPLOYER]

    def make_keys(self) -> None:
        keys = self.directory / "ssh"
        keys.mkdir(mode=0o700)
        for name in ("host", "user"):
            subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", str(keys / name)], check=True)
        (keys / "authorized_keys").write_text((keys / "user.pub").read_text())
        host_key = (keys / "host.pub").read_text().split()
        lines = [f"{robot.address} {host_key[0]} {host_key[1]}\n" for robot in self.robots.values()]
        (keys / "known_hosts").write_text("".join(lines))

    def sshd_config(self, robot: SshRobot) -> Path:
        keys = self.directory / "ssh"
        config = self.directory / f"sshd_{robot.host.name}.conf"
        config.write_text(
            f"ListenAddress {robot.address}\nHostKey {keys / 'host'}\nAuthorizedKeysFile {keys / 'authorized_keys'}\n"
            "PidFile none\nUsePAM no\nStrictModes no\nPermitRootLogin prohibit-password\nPasswordAuthentication no\n"
            "KbdInteractiveAuthentication no\nPrintMotd no\nPrintLastLog no\nSubsystem sftp internal-sftp\n"
        )
        return config

    def mount_private(self, robot: SshRobot, opt_size: str | None = None) -> None:
        for mount_point, options in PRIVATE_MOUNTS.items():
            if mount_point == "/opt" and opt_size:
                options = options.replace(PRIVATE_MOUNTS["/opt"].split(",")[0], f"size={opt_size}")
            robot.host.run(["mount", "-t", "tmpfs", "-o", options, "joshua-robot", mount_point], check=True)

    def start_sshd(self, robot: SshRobot) -> None:
        robot.host.run(["mkdir", "-p", "-m", "0755", "/run/sshd"], check=True)
        robot.host.run(["touch", "/var/log/lastlog", "/var/log/wtmp", "/var/log/btmp"], check=True)
        with open(self.directory / f"sshd_{robot.host.name}.log", "wb") as log:
            robot.sshd = robot.host.popen(
                ["/usr/sbin/sshd", "-D", "-e", "-f", str(self.sshd_config(robot))], stderr=log
            )

    def wait_listening(self) -> None:
        deadline = time.monotonic() + SSHD_READY_TIMEOUT_S
        for robot in (robot for robot in self.robots.values() if robot.sshd is not None):
            while f"{robot.address}:22 " not in robot.run(["ss", "-Hltn"]).stdout:
                assert robot.sshd.poll() is None, f"sshd of {robot.host.name} exited {robot.sshd.returncode}"
                assert time.monotonic() < deadline, f"sshd of {robot.host.name} is not listening"
                time.sleep(SSHD_POLL_S)

    def environment(self) -> dict:
        """What the deployer runs with: Ansible's files in the test directory, the test's SSH key and known_hosts."""
        keys = self.directory / "ssh"
        home = self.directory / "ansible"
        return dict(
            os.environ,
            ANSIBLE_HOME=str(home),
            ANSIBLE_LOCAL_TEMP=str(home / "tmp"),
            ANSIBLE_PRIVATE_KEY_FILE=str(keys / "user"),
            ANSIBLE_SSH_CONTROL_PATH_DIR=str(self.control_dir),
            ANSIBLE_REMOTE_USER="root",
            ANSIBLE_SSH_COMMON_ARGS=f"-o UserKnownHostsFile={keys / 'known_hosts'} -o StrictHostKeyChecking=yes",
            PATH=f"{VENV_BIN}:{os.environ.get('PATH', '')}",
        )

    def deploy(self, args: list[str], timeout: float = DEPLOY_TIMEOUT_S) -> subprocess.CompletedProcess:
        """`joshua-fleet ARGS...` on the deployer host; output captured as text."""
        return self.deployer.run(
            [str(VENV_BIN / "joshua-fleet"), *args],
            cwd=self.directory,
            env=self.environment(),
            capture_output=True,
            text=True,
            timeout=timeout,
        )


@contextmanager
def ssh_robots(
    directory: Path, names: list[str], without_sshd: tuple[str, ...] = (), opt_sizes: dict[str, str] | None = None
) -> Iterator[SshFleet]:
    """Robots `names` (host names as hosts.py takes them) with sshd running, and a deployer, for the block.
    Robots named in `without_sshd` get no sshd (an unreachable robot); `opt_sizes` gives some a smaller /opt
    (`{"arm2": "8m"}`: a full disk)."""
    with virtual_hosts(DEPLOYER, *names) as network, tempfile.TemporaryDirectory(prefix=CONTROL_DIR_PREFIX) as control:
        fleet = SshFleet(network, Path(directory), list(names), Path(control))
        fleet.make_keys()
        for name, robot in fleet.robots.items():
            fleet.mount_private(robot, (opt_sizes or {}).get(name))
            if name not in without_sshd:
                fleet.start_sshd(robot)
        fleet.wait_listening()
        yield fleet
