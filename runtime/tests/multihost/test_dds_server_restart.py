"""The Discovery Server stops mid-run and comes back: what keeps working meanwhile, and who is found again.

Endpoints matched before the server went away keep exchanging data (discovery is over for them);
participants that start while it is away find nobody; once it runs again, the clients announce
themselves to it and old and new participants find each other, without restarting any of them.

A server stopped with SIGINT tells its clients it leaves; a crashed one is dropped by its clients only
when its lease runs out. Started again before that, it meets clients that still hold the old server's
reliable-discovery state, and an old client may never learn of an endpoint announced after the restart
(seen in about 1 restart in 30 with the server's default 20 s lease). So the server runs with the short
lease of testsupport/dds_profiles.server_profile (2 s) and a crashed server is started again only after
it: that is the case tested here. bench/multihost_dds.py measures how long rediscovery takes.
"""

import signal
import time

import pytest

from testsupport.dds_processes import DISCOVERY_TIMEOUT_S, client_env, probe, ready, received, start_server
from testsupport.dds_profiles import ServerTiming, server_profile, write_profile

SERVER_TIMING = ServerTiming()
OUTAGE_S = 2 * SERVER_TIMING.lease_ms / 1000  # a crashed server is started again after its lease
NEW_SEQ = 1_000_000  # the first sequence number of the talker started while the server is away


@pytest.mark.parametrize("stop_signal", [signal.SIGKILL, signal.SIGINT], ids=["crashed", "stopped"])
def test_after_the_server_restarts_old_and_new_participants_find_each_other(hosts, ros_env, tmp_path, stop_signal):
    hosts.block_multicast()
    server_xml = tmp_path / "server.xml"
    server_xml.write_text(server_profile(SERVER_TIMING))
    server = start_server(hosts["robot"], ros_env, profile=server_xml)
    env = client_env(ros_env, write_profile(tmp_path / "client.xml", server=(hosts["robot"].address, 11811)))
    old_talker = probe(hosts["robot"], env, "talk")
    old_listener = probe(hosts["gpu"], env, "listen")
    assert received(old_listener), old_listener.tail()

    server.process.send_signal(stop_signal)
    server.process.wait()
    stopped = time.monotonic()
    new_listener = probe(hosts["gpu"], env, "listen", "--name", "new_listener")
    new_talker = probe(hosts["robot"], env, "talk", "--name", "new_talker", "--first-seq", str(NEW_SEQ))
    ready(new_listener, new_talker)
    time.sleep(max(0.0, OUTAGE_S - (time.monotonic() - stopped)))
    restarted = time.monotonic()
    assert new_listener.received_seqs() == []
    assert all(seq < NEW_SEQ for seq in old_listener.received_seqs())

    start_server(hosts["robot"], ros_env, profile=server_xml)
    assert received(new_listener), new_listener.tail()  # a new participant finds an old one
    found = old_listener.wait_for(lambda output: max(output.received_seqs()) >= NEW_SEQ, DISCOVERY_TIMEOUT_S)
    assert found, f"publishers seen by the old listener: {old_listener.of('publishers')}\n{old_listener.tail()}"
    sent_in_outage = [event["seq"] for event in old_talker.of("sent") if stopped < event["t"] < restarted]
    assert sent_in_outage and set(sent_in_outage) <= set(old_listener.received_seqs())  # matched endpoints went on
