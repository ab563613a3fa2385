"""The simulated computers of testsupport/hosts.py: wired to each other, private /dev/shm, cleaned up, links that fail."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from testsupport import host_namespaces, netem
from testsupport.hosts import virtual_hosts
from testsupport.probe_output import ProbeOutput

UDP_PORT = 9000  # inside a host's own namespace: no other process of the machine can hold it
WAIT_S = 10.0
POLL_S = 0.05
# Receives datagrams on UDP_PORT and prints each one's text (and "listening" once bound).
RECEIVER = f"""
import socket
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("0.0.0.0", {UDP_PORT}))
print("listening", flush=True)
while True:
    print(s.recv(100).decode(), flush=True)
"""
# Echoes datagrams on UDP_PORT back to their sender.
ECHO = f"""
import socket
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("0.0.0.0", {UDP_PORT}))
print("listening", flush=True)
while True:
    data, sender = s.recvfrom(100)
    s.sendto(data, sender)
"""


def send(host, address: str, text: str) -> None:
    code = f"import socket; socket.socket(socket.AF_INET, socket.SOCK_DGRAM).sendto({text!r}.encode(), ({address!r}, {UDP_PORT}))"
    host.run([sys.executable, "-c", code], check=True)


def start_receiver(host, code: str = RECEIVER) -> ProbeOutput:
    receiver = ProbeOutput(host.popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True))
    assert receiver.wait_for(lambda output: "listening\n" in output.lines(), WAIT_S)
    return receiver


def received_lines(receiver: ProbeOutput, wanted: str, timeout_s: float = WAIT_S) -> bool:
    """Whether the receiver printed `wanted` within `timeout_s`."""
    return receiver.wait_for(lambda output: f"{wanted}\n" in output.lines(), timeout_s)


def root_links() -> set[str]:
    return {
        link["ifname"]
        for link in json.loads(subprocess.run(["ip", "-j", "link"], capture_output=True, text=True, check=True).stdout)
    }


def started(process: subprocess.Popen, program: str) -> subprocess.Popen:
    """The process once it runs `program` (nsenter has entered the host's namespaces and exec'd it)."""
    deadline = time.monotonic() + WAIT_S
    while Path(f"/proc/{process.pid}/comm").read_text().strip() != program:
        assert time.monotonic() < deadline, f"{process.args} did not exec {program}"
        time.sleep(POLL_S)
    return process


def running(pid: int) -> bool:
    """Whether the process exists and is not a zombie waiting for its new parent to reap it."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def mount_namespace(pid: int) -> str:
    return os.readlink(f"/proc/{pid}/ns/mnt")


def test_hosts_reach_each_other_over_the_switch_and_nothing_is_added_to_the_machines_network():
    links_before = root_links()
    with virtual_hosts("robot", "gpu") as hosts:
        assert root_links() == links_before
        receiver = start_receiver(hosts["gpu"])
        send(hosts["robot"], hosts["gpu"].address, "hello")
        assert received_lines(receiver, "hello")
        addresses = hosts["gpu"].run(["ip", "-j", "-4", "addr", "show", "dev", "eth0"], capture_output=True, text=True)
        assert json.loads(addresses.stdout)[0]["addr_info"][0]["local"] == hosts["gpu"].address
    assert root_links() == links_before


def test_a_process_runs_inside_its_host_under_its_own_pid():
    with virtual_hosts("robot") as hosts:
        process = started(hosts["robot"].popen(["sleep", "60"]), "sleep")
        identified = subprocess.run(["ip", "netns", "identify", str(process.pid)], capture_output=True, text=True)
        assert identified.stdout.strip() == hosts["robot"].netns


def test_each_host_has_its_own_dev_shm_shared_by_all_its_processes():
    marker = f"joshua-host-test-{os.getpid()}"
    with virtual_hosts("robot", "gpu") as hosts:
        robot, gpu = hosts["robot"], hosts["gpu"]
        robot.run(["touch", f"/dev/shm/{marker}"], check=True)
        assert marker in robot.shm_files()
        assert marker not in gpu.shm_files()
        assert not Path("/dev/shm", marker).exists()
        first, second, other = (started(host.popen(["sleep", "60"]), "sleep") for host in (robot, robot, gpu))
        assert mount_namespace(first.pid) == mount_namespace(second.pid)
        assert mount_namespace(first.pid) not in (mount_namespace(other.pid), mount_namespace(os.getpid()))


def test_a_link_down_stops_every_packet_until_it_is_up_again():
    with virtual_hosts("robot", "gpu") as hosts:
        receiver = start_receiver(hosts["gpu"])
        send(hosts["robot"], hosts["gpu"].address, "before")
        assert received_lines(receiver, "before")
        hosts["gpu"].link_down()
        send(hosts["robot"], hosts["gpu"].address, "during")
        assert not received_lines(receiver, "during", timeout_s=1.0)
        hosts["gpu"].link_up()
        send(hosts["robot"], hosts["gpu"].address, "after")
        assert received_lines(receiver, "after")


def test_a_switch_can_drop_multicast_and_still_pass_unicast():
    group = "239.255.0.1"
    joined = RECEIVER.replace(
        'print("listening"',
        f'import struct; s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, struct.pack("4s4s", socket.inet_aton("{group}"), socket.inet_aton("0.0.0.0")))\nprint("listening"',
    )
    with virtual_hosts("robot", "gpu") as hosts:
        receiver = start_receiver(hosts["gpu"], joined)
        send(hosts["robot"], group, "multicast")
        assert received_lines(receiver, "multicast")
        hosts.block_multicast()
        send(hosts["robot"], group, "blocked")
        send(hosts["robot"], hosts["gpu"].address, "unicast")
        assert received_lines(receiver, "unicast")
        assert "blocked\n" not in receiver.lines()


def test_leaving_the_block_kills_the_hosts_processes_and_deletes_the_namespaces_also_after_an_error():
    with pytest.raises(RuntimeError, match="test body failed"):
        with virtual_hosts("robot", "gpu") as hosts:
            started = hosts["robot"].popen(["sleep", "60"])
            ignoring = hosts["gpu"].popen(["sh", "-c", "trap '' INT TERM; sleep 60 & wait"])
            names = [host.netns for host in hosts] + [hosts.switch]
            state_dir = hosts.state_dir
            raise RuntimeError("test body failed")
    assert started.poll() is not None and ignoring.poll() is not None
    assert not set(names) & set(host_namespaces.network_namespaces())
    assert not state_dir.exists()


def test_two_sets_at_once_are_apart():
    with virtual_hosts("robot") as first, virtual_hosts("robot") as second:
        assert first.set_name != second.set_name
        receiver = start_receiver(second["robot"])
        send(first["robot"], second["robot"].address, "crossed")  # the same address, in the other set
        assert not received_lines(receiver, "crossed", timeout_s=1.0)


def test_a_set_whose_maker_died_is_removed_by_the_next_one(tmp_path):
    report = tmp_path / "made.json"
    maker = f"""
import json, os, signal, subprocess
from testsupport.hosts import virtual_hosts
from testsupport.probe_output import ProbeOutput
with virtual_hosts("robot") as hosts:
    # Dies only once the sleeper is inside the robot: dying sooner races the sleeper's own entry into it.
    sleeper = hosts["robot"].popen(["sh", "-c", "echo inside; exec sleep 600"], stdout=subprocess.PIPE)
    assert sleeper.stdout.readline() == b"inside\\n"
    open({str(report)!r}, "w").write(json.dumps({{"set": hosts.set_name, "netns": hosts["robot"].netns, "pid": sleeper.pid}}))
    os.kill(os.getpid(), signal.SIGKILL)
"""
    died = subprocess.run([sys.executable, "-c", maker], cwd=Path(__file__).resolve().parents[3], timeout=60)
    assert died.returncode == -signal.SIGKILL
    made = json.loads(report.read_text())
    assert made["netns"] in host_namespaces.network_namespaces()
    with virtual_hosts("robot"):
        assert made["netns"] not in host_namespaces.network_namespaces()
        assert not (host_namespaces.STATE_ROOT / made["set"]).exists()
        assert not running(made["pid"])


def test_delay_is_emulated_where_the_kernel_has_netem_and_said_unavailable_where_not():
    delay_ms = 100.0
    with virtual_hosts("robot", "gpu") as hosts:
        reason = netem.unavailable_reason(hosts.switch)
        if reason:
            with pytest.raises(netem.NetemUnavailable, match="no netem queueing discipline"):
                hosts["robot"].impair(delay_ms=delay_ms)
            return
        start_receiver(hosts["gpu"], ECHO)
        hosts["robot"].impair(delay_ms=delay_ms)
        code = (
            "import socket, time; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.settimeout(10); "
            f"t = time.monotonic(); s.sendto(b'x', ({hosts['gpu'].address!r}, {UDP_PORT})); s.recv(10); "
            "print(time.monotonic() - t)"
        )
        round_trip = hosts["robot"].run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        assert float(round_trip.stdout) >= delay_ms / 1000
