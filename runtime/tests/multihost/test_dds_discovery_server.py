"""A Fast DDS Discovery Server on one host lets processes on every host find each other without multicast.

The server runs on host "robot" (started as the runtime's launcher starts it); the switch drops multicast,
so only the server can make participants meet. Clients name it in their participant profile
(testsupport/dds_profiles.py, the XML of docs/multihost-dds.md) or in ROS_DISCOVERY_SERVER.
"""

import signal
import time

from testsupport.dds_processes import (
    ABSENCE_WINDOW_S,
    START_TIMEOUT_S,
    client_env,
    probe,
    project_profile,
    ready,
    received,
    server_locator,
    start_server,
)
from testsupport.dds_profiles import write_profile

SERVER_STOP_TIMEOUT_S = 10.0
GRAPH_SETTLE_S = 5.0  # several discovery rounds after a super client saw the topic


def test_clients_named_in_their_profile_find_each_other_on_both_hosts_without_multicast(hosts, ros_env, tmp_path):
    hosts.block_multicast()
    profile = write_profile(tmp_path / "client.xml", server=(hosts["robot"].address, 11811))
    env = client_env(ros_env, profile)
    start_server(hosts["robot"], env)  # in the nodes' environment, as a supervisor starts it
    probe(hosts["robot"], env, "talk")
    remote = probe(hosts["gpu"], env, "listen")
    beside = probe(hosts["robot"], env, "listen")
    assert received(remote), remote.tail()
    assert received(beside), beside.tail()


def test_the_discovery_server_variable_makes_the_projects_profile_a_client(hosts, ros_env, tmp_path):
    hosts.block_multicast()
    start_server(hosts["robot"], ros_env)
    env = dict(
        client_env(ros_env, project_profile(tmp_path, images=True)), ROS_DISCOVERY_SERVER=server_locator(hosts["robot"])
    )
    probe(hosts["robot"], env, "talk")
    listener = probe(hosts["gpu"], env, "listen")
    assert received(listener), listener.tail()


def test_without_a_server_the_clients_find_nobody(hosts, ros_env, tmp_path):
    hosts.block_multicast()
    env = client_env(ros_env, write_profile(tmp_path / "client.xml", server=(hosts["robot"].address, 11811)))
    talker = probe(hosts["robot"], env, "talk")
    listener = probe(hosts["gpu"], env, "listen")
    ready(talker, listener)
    assert not received(listener, ABSENCE_WINDOW_S), listener.tail()


def test_a_client_sees_every_node_but_only_a_super_client_sees_every_topic(hosts, ros_env, tmp_path):
    hosts.block_multicast()
    start_server(hosts["robot"], ros_env)
    server = (hosts["robot"].address, 11811)
    client = client_env(ros_env, write_profile(tmp_path / "client.xml", server=server))
    super_client = client_env(ros_env, write_profile(tmp_path / "super.xml", server=server, role="SUPER_CLIENT"))
    variable = dict(ros_env, ROS_DISCOVERY_SERVER=server_locator(hosts["robot"]))
    talker = probe(hosts["robot"], client, "talk", "--name", "talker", "--topic", "/on_robot")
    listener = probe(hosts["robot"], client, "listen", "--name", "listener", "--topic", "/on_robot")
    assert received(listener), listener.tail()
    watchers = {
        "client": probe(hosts["gpu"], client, "graph", "--name", "as_client"),
        "super_client": probe(hosts["gpu"], super_client, "graph", "--name", "as_super_client"),
        "variable_super_client": probe(hosts["gpu"], dict(variable, ROS_SUPER_CLIENT="TRUE"), "graph", "--name", "v"),
        "profile_client_variable_super": probe(
            hosts["gpu"], dict(client, ROS_SUPER_CLIENT="TRUE"), "graph", "--name", "p"
        ),
    }
    ready(talker, *watchers.values())
    for watcher in watchers.values():
        assert watcher.wait_for(lambda output: "/talker" in output.last_graph()["nodes"], START_TIMEOUT_S), (
            watcher.tail()
        )
    seen = watchers["super_client"].wait_for(
        lambda output: "/on_robot" in output.last_graph()["topics"], START_TIMEOUT_S
    )
    assert seen, watchers["super_client"].tail()
    time.sleep(GRAPH_SETTLE_S)  # for the watchers that should not see the topic to have had every chance
    topics = {name: "/on_robot" in watcher.last_graph()["topics"] for name, watcher in watchers.items()}
    assert topics == {
        "client": False,  # nodes (from ros_discovery_info, a topic every node shares), not others' topics
        "super_client": True,
        "variable_super_client": True,
        "profile_client_variable_super": False,  # ROS_SUPER_CLIENT does not override a profile's CLIENT
    }


def test_the_server_stops_on_sigint_and_exits_0(hosts, ros_env):
    server = start_server(hosts["robot"], ros_env)
    server.process.send_signal(signal.SIGINT)
    assert server.process.wait(SERVER_STOP_TIMEOUT_S) == 0
    assert server.wait_for(lambda output: any("Server shut down" in line for line in output.lines()), START_TIMEOUT_S)
