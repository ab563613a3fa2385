"""Default (multicast) discovery between two hosts: it works over the subnet, not with the LOCALHOST range,
and not on a network that drops multicast (the reason for a Discovery Server)."""

from testsupport.dds_processes import ABSENCE_WINDOW_S, probe, ready, received


def test_a_talker_and_a_listener_on_two_hosts_discover_each_other_by_multicast(hosts, subnet_env):
    probe(hosts["robot"], subnet_env, "talk")
    listener = probe(hosts["gpu"], subnet_env, "listen")
    assert received(listener), listener.tail()


def test_the_localhost_range_keeps_a_process_from_the_other_hosts(hosts, ros_env):
    assert ros_env["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
    probe(hosts["robot"], ros_env, "talk")
    beside = probe(hosts["robot"], ros_env, "listen")
    remote = probe(hosts["gpu"], ros_env, "listen")
    ready(remote)
    assert received(beside), beside.tail()  # the talker runs and is found on its own host
    assert not received(remote, ABSENCE_WINDOW_S), remote.tail()


def test_a_network_that_drops_multicast_stops_default_discovery(hosts, subnet_env):
    hosts.block_multicast()
    talker = probe(hosts["robot"], subnet_env, "talk")
    listener = probe(hosts["gpu"], subnet_env, "listen")
    ready(talker, listener)
    assert not received(listener, ABSENCE_WINDOW_S), listener.tail()
