"""A generated robot on two simulated computers: start -> all hosts ready, and cross-host joint-state latency,
with and without a Discovery Server.

    .venv/bin/python bench/multihost.py [--rounds 5] [--seconds 10] [--quick]          (as root)

The robot (DESCRIPTION) has two hosts: "arm" with the leader (a MOCK_ENCODER_PUBLISHER at LEADER_HZ) and
"bench" with a MOCK_ACTUATOR_SUBSCRIBER following it. It is built with `joshuac build`, and each host's
generated supervisor.py runs inside its own simulated computer (testsupport/hosts.py: network namespaces
with their own /dev/shm on one switch), as tests/e2e/test_robot_on_simulated_computers.py runs them.
Two variants of the same robot take turns, round after round, so the machine's load falls on both alike:

  server      `discovery { server_host: "arm" }`: every process a client of the Discovery Server the
              arm's supervisor runs; the switch drops multicast, so nothing else could make them meet
  multicast   no `discovery { }` block: Fast DDS's multicast discovery over the hosts' subnet
              (ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET); the switch passes multicast

"start -> all hosts ready": from starting both supervisors to the last of them saying every node of its
host is ready (the Discovery Server and its watch included). "latency": a subscriber on "bench" in that
host's nodes' environment (support/joint_state_latency.py, with the leader topic's QoS) takes each
leader message's arrival minus its header stamp for --seconds, p50 and p99 over all rounds. Ratios:
server / multicast, measured in the same run. --quick: one round of 2 s, for the tests.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from support.described_nodes import PYTHON, compiled_settings

from testsupport.host_supervisors import ready, start_supervisors, stop_supervisors
from testsupport.hosts import virtual_hosts
from testsupport.joshuac_cli import joshuac

LEADER_HZ = 100.0
SERVER_PORT = 11811  # inside host arm's own network namespace: nothing else can hold it
READY_TIMEOUT_S = 120.0  # both supervisors ready, nodes started cold on a busy 2-core machine
FIRST_MESSAGE_TIMEOUT_S = 60.0
MARGIN_S = 30.0  # beyond the first message and the measurement, before the subscriber is taken for hung
LOG_TAIL_CHARS = 2000  # of each supervisor's output, when a turn fails
POLL_S = 0.01  # how often the supervisors' logs are read for their ready line
QUICK_SECONDS = 2.0
BENCH = Path(__file__).resolve().parent
HOSTS = ("arm", "bench")
LEADER_TOPIC = "/leader/joint_states"
DISCOVERY = f'discovery {{ server_host: "arm" port: {SERVER_PORT} }}'
DESCRIPTION = """
robot_config {{
  name: "multihost_bench"
  mode: MODE_TELEOPERATION
  host {{ name: "arm" address: "{arm}" }}
  host {{ name: "bench" address: "{bench}" }}
  {discovery}
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER host: "arm" topic_name: "{topic}" rate_hz: {rate:g} }}
  node {{
    name: "follower"
    type: MOCK_ACTUATOR_SUBSCRIBER
    host: "bench"
    topic_name: "{topic}"
    state_topic: "/follower/joint_states"
  }}
}}
"""


@dataclass
class Variant:
    name: str
    server: bool
    out: Path
    leader_topic: dict
    ready_s: list[float] = field(default_factory=list)
    latencies_s: list[float] = field(default_factory=list)

    def percentile_ms(self, q: float) -> float:
        return float(np.percentile(self.latencies_s, q)) * 1000


def build(variant_name: str, server: bool, network, workdir: Path) -> Variant:
    """The robot of this variant, built by joshuac into workdir/<name>/out."""
    text = DESCRIPTION.format(
        arm=network["arm"].address,
        bench=network["bench"].address,
        discovery=DISCOVERY if server else "",
        topic=LEADER_TOPIC,
        rate=LEADER_HZ,
    )
    source = workdir / variant_name / "multihost_bench.pbtxt"
    source.parent.mkdir(parents=True)
    source.write_text(text)
    out = source.parent / "out"
    built = joshuac("build", source, "-o", out)
    if built.returncode != 0:
        raise SystemExit(f"joshuac build failed:\n{built.stderr}")
    leader_topic = compiled_settings(text, path=str(source))["leader"]["topic"]
    return Variant(variant_name, server, out, leader_topic)


def subscriber_env(env: dict, out: Path) -> dict:
    """The environment of a process on host "bench" as its supervisor gives its nodes (the host's profile)."""
    profile = out / "hosts" / "bench" / "fastdds_profile.xml"
    return dict(env, FASTRTPS_DEFAULT_PROFILES_FILE=str(profile), PYTHONPATH=str(BENCH))


def measure_latency(host, env: dict, topic: dict, seconds: float) -> list[float]:
    spec = {"topic": topic, "seconds": seconds, "first_message_timeout_s": FIRST_MESSAGE_TIMEOUT_S}
    process = host.popen(
        [PYTHON, "-m", "support.joint_state_latency", json.dumps(spec)],
        cwd=BENCH, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        stdout, stderr = process.communicate(timeout=FIRST_MESSAGE_TIMEOUT_S + seconds + MARGIN_S)
    except subprocess.TimeoutExpired:
        process.kill()
        stdout, stderr = process.communicate()
    if not stdout.strip():
        raise SystemExit(f"the latency subscriber printed nothing:\n{stderr[-3000:]}")
    result = json.loads(stdout.strip().splitlines()[-1])
    if "error" in result:
        raise SystemExit(f"the latency subscriber: {result['error']}\n{stderr[-3000:]}")
    return result["latencies_s"]


def tails(logs: dict[str, Path]) -> str:
    return "\n".join(f"--- {name}:\n{path.read_text()[-LOG_TAIL_CHARS:]}" for name, path in logs.items())


def run_once(variant: Variant, network, env: dict, workdir: Path, seconds: float) -> None:
    """Start the variant's supervisors, time them to ready, measure latency, stop them."""
    network.block_multicast(variant.server)
    run_env = env if variant.server else dict(env, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET")
    run_dir = Path(tempfile.mkdtemp(prefix=f"{variant.name}-", dir=workdir))
    started = time.monotonic()
    supervisors, logs = start_supervisors(network, variant.out, run_dir, run_env)
    try:
        deadline = started + READY_TIMEOUT_S
        while not all(ready(path.read_text()) for path in logs.values()):
            ended = [name for name, supervisor in supervisors.items() if supervisor.poll() is not None]
            if ended or time.monotonic() > deadline:
                raise SystemExit(f"{variant.name}: not ready:\n{tails(logs)}")
            time.sleep(POLL_S)
        variant.ready_s.append(time.monotonic() - started)
        latencies = measure_latency(
            network["bench"], subscriber_env(run_env, variant.out), variant.leader_topic, seconds
        )
        variant.latencies_s.extend(latencies)
    finally:
        codes = stop_supervisors(supervisors)
    if codes != dict.fromkeys(HOSTS, 0):
        raise SystemExit(f"{variant.name}: supervisors exited {codes}:\n{tails(logs)}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5, help="turns each variant takes")
    parser.add_argument("--seconds", type=float, default=10.0, help="latency measurement per turn")
    parser.add_argument("--quick", action="store_true", help="one round of 2 s (for the tests)")
    args = parser.parse_args()
    if os.geteuid() != 0:
        raise SystemExit("multihost needs root: it makes network namespaces")
    rounds = 1 if args.quick else max(1, args.rounds)
    seconds = QUICK_SECONDS if args.quick else args.seconds
    from support.ros_env import bench_environment

    env = bench_environment("multihost")
    with tempfile.TemporaryDirectory(prefix="joshua-bench-multihost-robot-") as tmp, virtual_hosts(*HOSTS) as network:
        variants = [build("server", True, network, Path(tmp)), build("multicast", False, network, Path(tmp))]
        for round_index in range(rounds):  # who goes first alternates, so neither always follows the other
            for variant in variants if round_index % 2 == 0 else variants[::-1]:
                run_once(variant, network, env, Path(tmp), seconds)
    server, multicast = variants
    print(
        f"generated robot on hosts {' and '.join(HOSTS)}: leader at {LEADER_HZ:g} Hz on arm, subscriber on bench; "
        f"{rounds} round(s), {seconds:g} s of latency per turn, variants in turn"
    )
    print(f"{'variant':<34} {'ready s (median, max)':>22}  {'p50 ms':>8}  {'p99 ms':>8}  messages")
    for variant, label in ((server, "Discovery Server, no multicast"), (multicast, "multicast discovery (SUBNET)")):
        print(
            f"{label:<34} {statistics.median(variant.ready_s):13.2f} ({max(variant.ready_s):5.2f})  "
            f"{variant.percentile_ms(50):8.2f}  {variant.percentile_ms(99):8.2f}  {len(variant.latencies_s)}"
        )
    print(
        f"Discovery Server / multicast: start -> all hosts ready "
        f"{statistics.median(server.ready_s) / statistics.median(multicast.ready_s):5.2f}x, latency p50 "
        f"{server.percentile_ms(50) / multicast.percentile_ms(50):5.2f}x, p99 "
        f"{server.percentile_ms(99) / multicast.percentile_ms(99):5.2f}x"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
