"""A real ACT served with action chunks keeps the follower commanded while each model call lasts many control periods.

The tiny ACT of testsupport/tiny_act.py (LeRobot's ResNet-18 backbone on a 320x240 camera, chunks of 100
actions at 30 Hz) runs on the CPU in an INFERENCE node process whose topic is a JointTrajectory; a mock
camera sends it JPEG CompressedImages and a mock encoder joint states, both node processes too. This test
is the follower: it takes the chunks with the actuators' own rule (nodes/trajectory_follower.py) at
CONTROL_HZ and counts the commands it executes. Rates belong to bench/remote_inference.py.
"""

import signal

import numpy as np
import pytest
from ai_support import NodeProcess, compiled, mock_encoder, node_block
from trajectory_msgs.msg import JointTrajectory

from joshua_core import so100
from joshua_runtime.nodes.trajectory_follower import TrajectoryFollower, chunk_from_trajectory, now_s, ros_seconds
from testsupport import tiny_act

JOINTS = list(so100.SO100_JOINTS)
CONTROL_HZ = 500.0  # a call of the tiny ACT takes 25 ms or more even on a quiet machine
POLICY_HZ = 30.0
MODEL_CALLS = 6  # chunks to receive after the first
MIN_COMMANDS_PER_CALL = 5
CHUNKS_TIMEOUT_S = 180.0
CHUNKS_TOPIC = "/arm/chunks"
RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}


def description(policy_dir) -> dict:
    return compiled(
        "MODE_INFERENCE",
        node_block(
            "camera",
            "MOCK_CAMERA_PUBLISHER",
            topic_name=tiny_act.CAMERA_TOPIC,
            message_type="sensor_msgs/msg/CompressedImage",
            width=tiny_act.WIDTH,
            height=tiny_act.HEIGHT,
            rate_hz=POLICY_HZ,
        ),
        mock_encoder("follower", tiny_act.STATE_TOPIC, JOINTS, 50.0),
        node_block(
            "policy",
            "INFERENCE",
            topic_name=CHUNKS_TOPIC,
            message_type="trajectory_msgs/msg/JointTrajectory",
            model_path=str(policy_dir),
            input_topics=[tiny_act.CAMERA_TOPIC, tiny_act.STATE_TOPIC],
            rate_hz=POLICY_HZ,
        ),
    )


class Follower:
    """The actuators' chunk rule at CONTROL_HZ; counts executed commands and chunk arrivals."""

    def __init__(self, peer):
        self.peer = peer
        self.rule = TrajectoryFollower(len(JOINTS))
        self.arrivals: list[float] = []
        self.commands: list[float] = []  # when each command from a chunk in force was executed
        self.chunks: list[JointTrajectory] = []
        self.dropped: list[str] = []  # why each chunk was dropped ("" when followed)
        peer.node.create_subscription(JointTrajectory, CHUNKS_TOPIC, self.receive, 10)
        peer.node.create_timer(1.0 / CONTROL_HZ, self.tick)

    def receive(self, message: JointTrajectory) -> None:
        now = now_s(self.peer.node)
        self.chunks.append(message)
        self.arrivals.append(now)
        self.dropped.append(self.rule.accept(chunk_from_trajectory(message, JOINTS, now), now))

    def tick(self) -> None:
        now = now_s(self.peer.node)
        if self.rule.executing(now):
            self.commands.append(now)


@pytest.mark.timeout(600)
def test_commands_keep_flowing_while_a_real_act_call_lasts_many_control_periods(trained_act, ai_env, ros_peer):
    settings = description(trained_act)
    follower = Follower(ros_peer)
    nodes = [NodeProcess(settings[name], ai_env) for name in ("camera", "follower", "policy")]
    try:
        nodes[2].wait_for(r"ready: act policy")
        received = ros_peer.spin_until(lambda: len(follower.arrivals) > MODEL_CALLS, CHUNKS_TIMEOUT_S)
        assert received, f"{len(follower.arrivals)} chunks:\n{nodes[2].output}"
        nodes[2].wait_for(r"first action chunk published")
        arrivals, commands = np.array(follower.arrivals), np.array(follower.commands)

        first = follower.chunks[0]
        assert list(first.joint_names) == JOINTS and len(first.points) == tiny_act.CHUNK_SIZE
        steps = [ros_seconds(p.time_from_start) for p in first.points]
        assert steps == pytest.approx(np.arange(tiny_act.CHUNK_SIZE) / POLICY_HZ, abs=1e-6)
        # Stamped with the observation's time: before the chunk arrived, after the node started.
        stamps = np.array([ros_seconds(c.header.stamp) for c in follower.chunks])
        assert np.all(stamps < arrivals) and np.all(np.diff(stamps) > 0)

        assert follower.dropped == [""] * len(follower.dropped), follower.dropped
        per_call = [np.count_nonzero((commands > a) & (commands <= b)) for a, b in zip(arrivals, arrivals[1:])]
        assert min(per_call) >= MIN_COMMANDS_PER_CALL, per_call
        chunk_length_s = (tiny_act.CHUNK_SIZE - 1) / POLICY_HZ
        in_run = commands[(commands > arrivals[0]) & (commands <= arrivals[-1])]
        assert np.max(np.diff(in_run)) < chunk_length_s, np.max(np.diff(in_run))
        for node in nodes:
            assert node.stop(signal.SIGINT) == 0, node.output
    finally:
        for node in nodes:
            node.kill()
