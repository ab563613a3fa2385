"""A real ACT on another computer than the arm and its camera keeps the follower commanded while each model
call lasts many control periods.

Two simulated computers (testsupport/hosts.py: network namespaces with their own /dev/shm on one switch):
"robot" runs the mock camera (JPEG CompressedImages, as a camera sends them to another computer), the
arm's mock encoder and the follower (chunk_follower.py, the actuators' chunk rule at CONTROL_HZ, a process
of that host); "gpu" runs the INFERENCE node serving the tiny ACT's chunks on its CPU. Everything the
policy sees and every chunk crosses the link between them. Rates belong to bench/remote_inference.py (c).
"""

import json
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from ai_support import NodeProcess
from chunk_support import (
    CHUNKS_TIMEOUT_S,
    CHUNKS_TOPIC,
    COMPRESSED_IMAGE,
    CONTROL_HZ,
    JOINTS,
    MODEL_CALLS,
    assert_commands_kept_flowing,
    description,
)

from testsupport.hosts import virtual_hosts

pytestmark = pytest.mark.process  # network namespaces, and ai from its fixtures

CHUNK_FOLLOWER = Path(__file__).resolve().parent / "chunk_follower.py"
FOLLOWER_EXIT_MARGIN_S = 30.0  # beyond CHUNKS_TIMEOUT_S: its last spin, shutdown and output
PLACES = {"camera": "robot", "follower": "robot", "policy": "gpu"}


@pytest.mark.timeout(600)
def test_commands_keep_flowing_while_the_act_runs_on_another_computer(trained_act, ai_env):
    settings = description(trained_act, COMPRESSED_IMAGE)
    env = dict(ai_env, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET")  # the subnet is the hosts' own switch
    spec = {
        "topic": CHUNKS_TOPIC,
        "joints": JOINTS,
        "control_hz": CONTROL_HZ,
        "chunks": MODEL_CALLS,
        "timeout_s": CHUNKS_TIMEOUT_S,
    }
    with virtual_hosts(*sorted(set(PLACES.values()))) as hosts:
        follower = hosts["robot"].popen(
            [sys.executable, CHUNK_FOLLOWER, json.dumps(spec)],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        nodes = {name: NodeProcess(settings[name], env, hosts[host]) for name, host in PLACES.items()}
        try:
            nodes["policy"].wait_for(r"ready: act policy")
            stdout, stderr = follower.communicate(timeout=CHUNKS_TIMEOUT_S + FOLLOWER_EXIT_MARGIN_S)
            assert follower.returncode == 0, stderr
            record = json.loads(stdout.strip().splitlines()[-1])
            assert len(record["arrivals"]) > MODEL_CALLS, f"{len(record['arrivals'])} chunks:\n{nodes['policy'].output}"
            nodes["policy"].wait_for(r"first action chunk published")
            assert_commands_kept_flowing(record)
            for node in nodes.values():
                assert node.stop(signal.SIGINT) == 0, node.output
        finally:
            for node in nodes.values():
                node.kill()
