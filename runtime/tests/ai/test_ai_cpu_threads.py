"""An INFERENCE node's torch worker threads sleep when they wait, so a busy machine does not stall its model calls.

PyTorch's wheels run their CPU kernels on libgomp (OpenMP) threads, which by default spin for a while
at every barrier before they sleep. On a machine with as many busy processes as cores, a spinning
worker holds a core the other worker needs to finish the same kernel: bench/remote_inference.py
measured a tiny ACT's chunk latency at p50 1.2 s in a node against 0.1 s in LeRobot's own policy
server. The node sets OMP_WAIT_POLICY=PASSIVE (unless its environment names a policy) before torch
loads; libgomp reports the policy it runs with when OMP_DISPLAY_ENV=VERBOSE, which these tests read.
"""

import re
import signal

import pytest
from ai_support import NodeProcess
from chunk_support import RAW_IMAGE, description

SPIN_COUNT = re.compile(r"GOMP_SPINCOUNT = '(\d+)'")
WAIT_POLICY_VARIABLE = "OMP_WAIT_POLICY"


def spin_count_of_ready_node(policy_dir, env: dict) -> int:
    """Start the node with libgomp's verbose report on; the spin count it reports once the policy is ready."""
    node = NodeProcess(description(policy_dir, RAW_IMAGE)["policy"], dict(env, OMP_DISPLAY_ENV="VERBOSE"))
    try:
        node.wait_for(r"ready: act policy")
        reported = SPIN_COUNT.findall(node.output)
        assert len(reported) == 1, f"libgomp reported its settings {len(reported)} times:\n{node.output}"
        assert node.stop(signal.SIGINT) == 0, node.output
        return int(reported[0])
    finally:
        node.kill()


@pytest.mark.timeout(300)
def test_torch_worker_threads_of_an_inference_node_never_spin(trained_act, ai_env):
    env = {key: value for key, value in ai_env.items() if key not in (WAIT_POLICY_VARIABLE, "GOMP_SPINCOUNT")}
    assert spin_count_of_ready_node(trained_act, env) == 0


@pytest.mark.timeout(300)
def test_a_wait_policy_set_by_the_user_is_kept(trained_act, ai_env):
    env = dict(ai_env, **{WAIT_POLICY_VARIABLE: "ACTIVE"})
    env.pop("GOMP_SPINCOUNT", None)
    assert spin_count_of_ready_node(trained_act, env) > 0
