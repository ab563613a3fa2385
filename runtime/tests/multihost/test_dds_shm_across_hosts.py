"""Shared memory inside a host, UDP between hosts: 640x480 images under the project's images profile
(a 16 MiB shared-memory segment plus UDP), with default discovery and with a Discovery Server.

Fast DDS offers a shared-memory locator only to participants of its own host (it compares a host id made
from the host name and its IPv4 addresses), so the listener on the talker's host reads the segment and
the listener on the other host gets UDP. The interface counters tell which: an image crossing the link
is 921,600 bytes on eth0; one read from shared memory adds nothing to eth0 or lo. Each host's /dev/shm
is its own: the other host's segments never appear in it.
"""

import time

import pytest

from testsupport.dds_processes import client_env, probe, received, start_server
from testsupport.dds_profiles import write_profile

IMAGE_BYTES = 640 * 480 * 3
RATE_HZ = 10.0
WINDOW_S = 4.0
QOS = ["--depth", "2"]


@pytest.mark.parametrize("discovery", ["multicast", "server"])
def test_images_go_by_shared_memory_on_their_host_and_by_udp_to_the_other(hosts, subnet_env, tmp_path, discovery):
    server = None
    if discovery == "server":
        hosts.block_multicast()
        start_server(hosts["robot"], subnet_env)
        server = (hosts["robot"].address, 11811)
    env = client_env(subnet_env, write_profile(tmp_path / "images.xml", images=True, server=server))
    robot, gpu = hosts["robot"], hosts["gpu"]
    probe(robot, env, "talk", "--size", str(IMAGE_BYTES), "--rate", str(RATE_HZ), *QOS)
    beside = probe(robot, env, "listen", "--name", "beside", *QOS)
    remote = probe(gpu, env, "listen", "--name", "remote", *QOS)
    assert received(beside) and received(remote), beside.tail() + remote.tail()

    before = {"robot eth0": robot.counters(), "robot lo": robot.counters("lo"), "gpu eth0": gpu.counters()}
    counted = {"beside": len(beside.of("received")), "remote": len(remote.of("received"))}
    time.sleep(WINDOW_S)
    after = {"robot eth0": robot.counters(), "robot lo": robot.counters("lo"), "gpu eth0": gpu.counters()}
    images = {
        name: len(listener.of("received")) - counted[name]
        for name, listener in (("beside", beside), ("remote", remote))
    }
    moved = {name: after[name]["tx_bytes"] - before[name]["tx_bytes"] for name in ("robot lo",)}
    arrived = after["gpu eth0"]["rx_bytes"] - before["gpu eth0"]["rx_bytes"]

    assert all(event["bytes"] == IMAGE_BYTES for event in beside.of("received") + remote.of("received"))
    assert images["beside"] > 0 and images["remote"] > 0, images
    assert arrived >= images["remote"] * IMAGE_BYTES  # every image the remote listener got crossed the link
    assert moved["robot lo"] < IMAGE_BYTES  # the listener beside read shared memory, not loopback UDP

    robot_segments = {name for name in robot.shm_files() if name.startswith("fastrtps_") and "port" not in name}
    gpu_segments = {name for name in gpu.shm_files() if name.startswith("fastrtps_") and "port" not in name}
    assert robot_segments and gpu_segments and not robot_segments & gpu_segments
