"""A real ACT served with action chunks keeps the follower commanded while each model call lasts many control periods.

The tiny ACT of testsupport/tiny_act.py (LeRobot's ResNet-18 backbone on a 320x240 camera, chunks of 100
actions at 30 Hz) runs on the CPU in an INFERENCE node process whose topic is a JointTrajectory; a mock
camera sends it raw Images and a mock encoder joint states, both node processes too. This test
is the follower: it takes the chunks with the actuators' own rule (nodes/trajectory_follower.py) at
CONTROL_HZ and counts the commands it executes. Rates belong to bench/remote_inference.py.
"""

import signal

import pytest
from ai_support import NodeProcess
from chunk_follower import ChunkFollower
from chunk_support import (
    CHUNKS_TIMEOUT_S,
    CHUNKS_TOPIC,
    CONTROL_HZ,
    JOINTS,
    MODEL_CALLS,
    RAW_IMAGE,
    assert_commands_kept_flowing,
    description,
)


@pytest.mark.timeout(600)
def test_commands_keep_flowing_while_a_real_act_call_lasts_many_control_periods(trained_act, ai_env, ros_peer):
    settings = description(trained_act, RAW_IMAGE)
    follower = ChunkFollower(ros_peer.node, CHUNKS_TOPIC, JOINTS, CONTROL_HZ)
    nodes = [NodeProcess(settings[name], ai_env) for name in ("camera", "follower", "policy")]
    try:
        nodes[2].wait_for(r"ready: act policy")
        received = ros_peer.spin_until(lambda: len(follower.arrivals) > MODEL_CALLS, CHUNKS_TIMEOUT_S)
        assert received, f"{len(follower.arrivals)} chunks:\n{nodes[2].output}"
        nodes[2].wait_for(r"first action chunk published")
        assert_commands_kept_flowing(follower.record())
        for node in nodes:
            assert node.stop(signal.SIGINT) == 0, node.output
    finally:
        for node in nodes:
            node.kill()
