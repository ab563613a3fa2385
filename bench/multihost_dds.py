"""Discovery and recovery times of Fast DDS between two hosts: multicast, a Discovery Server, restarts, link outages.

    .venv/bin/python bench/multihost_dds.py [--runs 5] [--quick]

Two simulated computers (testsupport/hosts.py: network namespaces with their own /dev/shm on one
switch; needs root), rclpy probes (testsupport/dds_probe.py: a talker at 20 Hz on "robot", listeners
on "gpu") with the participant profiles of docs/multihost-dds.md (testsupport/dds_profiles.py: the
project's discovery timing; with a server, the client settings and a switch that drops multicast).
Each case is run --runs times; the figures are medians (and the worst run) in seconds:

  first discovery     both probes up -> first message, with multicast and with the Discovery Server
  server restarted    a crashed server started again after its lease (2 s) -> a listener started while
                      it was away gets its first message; an old listener gets one from a new talker
  link down 5 s       link up -> first message again (RELIABLE and BEST_EFFORT), messages lost
  link down > lease   link up -> first message, after the peer was dropped (lease 3 s, 6 s down)
  watch               link down -> the Discovery Server watch says "unreachable"

Ratios compare each time with first discovery by multicast, measured in the same run.
--quick: one run of each case, the link down 1 s and 3 s > a lease of 1.5 s, a server lease of 1 s (for the tests).
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from testsupport.dds_processes import ROOT, client_env, probe, ready, received, start_server
from testsupport.dds_profiles import ServerTiming, Timing, server_profile, write_profile
from testsupport.hosts import virtual_hosts
from testsupport.probe_output import ProbeOutput

RATE_HZ = 20.0
OUTAGE_S, QUICK_OUTAGE_S = 5.0, 1.0  # at RATE_HZ both outages outlast the RELIABLE history of DEPTH
DEPTH = 10
SHORT_LEASE = Timing(lease_ms=3000, announcement_ms=1000)
QUICK_SHORT_LEASE = Timing(lease_ms=1500, announcement_ms=500)
SERVER_TIMING, QUICK_SERVER_TIMING = ServerTiming(), ServerTiming(lease_ms=1000, announcement_ms=250)
WAIT_S = 60.0  # anything that should happen and has not by then ends the bench
BASE_DOMAIN = 150


def first_message_after(listener: ProbeOutput, after_s: float, min_seq: int = 0) -> float:
    """Seconds from `after_s` to the first message the listener got after it (numbered at least `min_seq`)."""
    arrived = listener.wait_for(
        lambda output: any(e["t"] > after_s and e["seq"] >= min_seq for e in output.of("received")), WAIT_S
    )
    if not arrived:
        raise SystemExit(f"no message within {WAIT_S:g} s:\n{listener.tail()}")
    return min(e["t"] for e in listener.of("received") if e["t"] > after_s and e["seq"] >= min_seq) - after_s


def first_discovery(env: dict, tmp: Path, server: bool) -> float:
    with virtual_hosts("robot", "gpu") as hosts:
        profile = None
        if server:
            hosts.block_multicast()
            start_server(hosts["robot"], env)
            profile = write_profile(tmp / "client.xml", server=(hosts["robot"].address, 11811))
        else:
            profile = write_profile(tmp / "participant.xml")
        talker = probe(hosts["robot"], client_env(env, profile), "talk", "--rate", str(RATE_HZ))
        listener = probe(hosts["gpu"], client_env(env, profile), "listen")
        ready(talker, listener)
        both_up = max(talker.of("ready")[0]["t"], listener.of("ready")[0]["t"])
        return first_message_after(listener, both_up)


def server_restarted(env: dict, tmp: Path, timing: ServerTiming = SERVER_TIMING) -> tuple[float, float]:
    """(new listener <- old talker, old listener <- new talker), seconds after the server runs again."""
    with virtual_hosts("robot", "gpu") as hosts:
        hosts.block_multicast()
        server_xml = tmp / "server.xml"
        server_xml.write_text(server_profile(timing))
        server = start_server(hosts["robot"], env, profile=server_xml)
        clients = client_env(env, write_profile(tmp / "client.xml", server=(hosts["robot"].address, 11811)))
        probe(hosts["robot"], clients, "talk", "--rate", str(RATE_HZ))
        old_listener = probe(hosts["gpu"], clients, "listen")
        received(old_listener)
        server.process.kill()
        server.process.wait()
        new_listener = probe(hosts["gpu"], clients, "listen", "--name", "new_listener")
        new_talker = probe(hosts["robot"], clients, "talk", "--name", "new_talker", "--first-seq", "1000000")
        ready(new_listener, new_talker)
        time.sleep(2 * timing.lease_ms / 1000)
        start_server(hosts["robot"], env, profile=server_xml)
        running = time.monotonic()
        return first_message_after(new_listener, running), first_message_after(old_listener, running, 1_000_000)


def link_down(env: dict, tmp: Path, qos: list[str], timing: Timing, outage_s: float) -> tuple[float, int, int]:
    """(link up -> first message, messages lost, messages sent during the outage)."""
    with virtual_hosts("robot", "gpu") as hosts:
        profile = client_env(env, write_profile(tmp / "participant.xml", timing=timing))
        talker = probe(hosts["robot"], profile, "talk", "--rate", str(RATE_HZ), *qos)
        listener = probe(hosts["gpu"], profile, "listen", *qos)
        received(listener, at_least=int(RATE_HZ))
        hosts["gpu"].link_down()
        down = time.monotonic()
        time.sleep(outage_s)
        hosts["gpu"].link_up()
        up = time.monotonic()
        resumed = first_message_after(listener, up)
        sent = {e["seq"] for e in talker.of("sent") if down < e["t"] < up}
        return resumed, len(sent - set(listener.received_seqs())), len(sent)


def watch_detection(env: dict) -> float:
    """Link down -> the watch's "unreachable" line, seconds."""
    with virtual_hosts("robot", "gpu") as hosts:
        start_server(hosts["robot"], env)
        command = [
            sys.executable,
            "-m",
            "joshua_runtime.discovery.watch",
            "--server",
            f"{hosts['robot'].address}:11811",
        ]
        process = hosts["gpu"].popen(
            command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
        )
        output = ProbeOutput(process)
        if not output.wait_for(lambda o: any("reachable:" in line for line in o.lines()), WAIT_S):
            raise SystemExit(f"the watch never found the server:\n{output.tail()}")
        hosts["gpu"].link_down()
        down = time.monotonic()
        if not output.wait_for(lambda o: any("unreachable:" in line for line in o.lines()), WAIT_S):
            raise SystemExit(f"the watch never said unreachable:\n{output.tail()}")
        return time.monotonic() - down


def summary(values: list[float]) -> str:
    return f"{statistics.median(values):6.2f} s (worst {max(values):5.2f})"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5, help="runs of each case")
    parser.add_argument("--quick", action="store_true", help="one run of each case, shorter outages (for the tests)")
    args = parser.parse_args()
    if os.geteuid() != 0:
        raise SystemExit("multihost_dds needs root: it makes network namespaces")
    runs = 1 if args.quick else max(1, args.runs)
    outage_s, short_lease = (QUICK_OUTAGE_S, QUICK_SHORT_LEASE) if args.quick else (OUTAGE_S, SHORT_LEASE)
    lease_s = short_lease.lease_ms / 1000
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET", PYTHONUNBUFFERED="1")
    env.setdefault("ROS_DOMAIN_ID", str(BASE_DOMAIN + os.getpid() % 50))
    figures: dict[str, list[float]] = {}
    losses: dict[str, list[tuple[int, int]]] = {}
    reliable, best_effort = ["--depth", str(DEPTH)], ["--reliability", "best_effort"]
    with tempfile.TemporaryDirectory(prefix="joshua-bench-multihost-") as tmp:
        for _ in range(runs):  # the cases take turns, so load falls on them alike
            figures.setdefault("first discovery, multicast", []).append(first_discovery(env, Path(tmp), server=False))
            figures.setdefault("first discovery, Discovery Server", []).append(
                first_discovery(env, Path(tmp), server=True)
            )
            new, old = server_restarted(env, Path(tmp), QUICK_SERVER_TIMING if args.quick else SERVER_TIMING)
            figures.setdefault("server restarted: new <- old", []).append(new)
            figures.setdefault("server restarted: old <- new", []).append(old)
            for name, qos in (("RELIABLE depth 10", reliable), ("BEST_EFFORT", best_effort)):
                resumed, lost, sent = link_down(env, Path(tmp), qos, Timing(), outage_s)
                figures.setdefault(f"link down {outage_s:g} s, {name}: resumed", []).append(resumed)
                losses.setdefault(f"link down {outage_s:g} s, {name}", []).append((lost, sent))
            resumed, _, _ = link_down(env, Path(tmp), [], short_lease, 2 * lease_s)
            figures.setdefault(f"link down {2 * lease_s:g} s > lease {lease_s:g} s: found again", []).append(resumed)
            figures.setdefault("watch: link down -> unreachable", []).append(watch_detection(env))
    floor = statistics.median(figures["first discovery, multicast"])
    print(f"{runs} run(s) per case, talker at {RATE_HZ:g} Hz on one host, listener on the other")
    for name, values in figures.items():
        print(f"{name:<42} {summary(values)}  {statistics.median(values) / floor:5.2f}x first discovery by multicast")
    for name, counts in losses.items():
        lost, sent = zip(*counts)
        print(f"{name:<42} lost {statistics.median(lost):.1f} of {statistics.median(sent):.1f} messages sent during it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
