"""The link between two hosts goes down for 5 s: discovery survives it and data flows again, with the losses
the QoS implies; a link down for longer than the lease drops the peer, which is found again after.

The project's participant profile (testsupport/dds_profiles.py, as templates/fastdds_profile.xml.j2: lease
10 s, announcements every 1 s). A talker at RATE_HZ on "robot", a listener on "gpu", the link of "gpu"
down for OUTAGE_S; messages are numbered, so the listener's numbers tell what was lost.
"""

import time

import pytest

from testsupport.dds_processes import DISCOVERY_TIMEOUT_S, client_env, probe, received
from testsupport.dds_profiles import Timing, write_profile

RATE_HZ = 20.0
OUTAGE_S = 5.0
DEPTH = 10
SETTLE_S = 3.0  # after the link is back: repairs and a few fresh messages


def run_outage(hosts, env, qos: list[str], outage_s: float):
    """Talk across the link, take it down for `outage_s`; (sent during the outage, received, listener)."""
    talker = probe(hosts["robot"], env, "talk", "--rate", str(RATE_HZ), *qos)
    listener = probe(hosts["gpu"], env, "listen", *qos)
    assert received(listener, at_least=int(RATE_HZ)), listener.tail()
    hosts["gpu"].link_down()
    down = time.monotonic()
    time.sleep(outage_s)
    up = time.monotonic()  # before the link is up: what is sent while `ip link set up` runs may pass
    hosts["gpu"].link_up()
    last_sent_in_outage = max(event["seq"] for event in talker.of("sent") if event["t"] < up)
    assert listener.wait_for(lambda output: max(output.received_seqs()) > last_sent_in_outage, DISCOVERY_TIMEOUT_S), (
        listener.tail()
    )
    time.sleep(SETTLE_S)
    in_outage = {event["seq"] for event in talker.of("sent") if down < event["t"] < up}
    return in_outage, listener.received_seqs(), listener


@pytest.fixture
def project_env(subnet_env, tmp_path):
    return client_env(subnet_env, write_profile(tmp_path / "participant.xml"))


def test_reliable_volatile_resumes_and_delivers_only_what_the_history_still_holds(hosts, project_env):
    in_outage, seqs, _ = run_outage(hosts, project_env, ["--depth", str(DEPTH)], OUTAGE_S)
    assert seqs == sorted(set(seqs))  # in order, no duplicate
    delivered = in_outage & set(seqs)
    assert len(delivered) <= DEPTH  # the rest was replaced in the writer's history before the link came back
    assert len(in_outage) - len(delivered) >= len(in_outage) - DEPTH > 0
    # Nothing lost once the writer is in touch again: what it sent after the link came up but before its next
    # exchange with the reader is in the outage's position (on a busy machine more than DEPTH of them).
    resumed = min(seq for seq in seqs if seq > max(in_outage))
    assert set(range(resumed, seqs[-1] + 1)) <= set(seqs)


def test_reliable_with_a_history_longer_than_the_outage_loses_nothing(hosts, project_env):
    depth = int(2 * OUTAGE_S * RATE_HZ)
    in_outage, seqs, _ = run_outage(hosts, project_env, ["--depth", str(depth)], OUTAGE_S)
    assert set(range(seqs[0], seqs[-1] + 1)) == set(seqs) and in_outage <= set(seqs)


def test_best_effort_loses_what_was_sent_during_the_outage_and_goes_on(hosts, project_env):
    in_outage, seqs, _ = run_outage(hosts, project_env, ["--reliability", "best_effort"], OUTAGE_S)
    assert not in_outage & set(seqs)
    assert seqs[-1] > max(in_outage)


def test_a_link_down_longer_than_the_lease_drops_the_peer_and_finds_it_again(hosts, subnet_env, tmp_path):
    timing = Timing(lease_ms=3000, announcement_ms=1000)  # short lease, so the test needs no long outage
    env = client_env(subnet_env, write_profile(tmp_path / "participant.xml", timing=timing))
    in_outage, seqs, listener = run_outage(hosts, env, [], outage_s=2 * timing.lease_ms / 1000)
    counts = [event["count"] for event in listener.of("publishers")]
    assert counts[-3:] == [1, 0, 1], counts  # matched, dropped when the lease ran out, matched again
    assert not in_outage & set(seqs)  # a new match starts from the newest messages (VOLATILE)
