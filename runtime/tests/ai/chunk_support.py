"""What the chunked-inference tests share: the robot they describe and what the follower's record must show.

The tiny ACT of testsupport/tiny_act.py (LeRobot's ResNet-18 backbone on a 320x240 camera, chunks of 100
actions at 30 Hz) serves chunks on a JointTrajectory topic, fed by a mock camera and a mock encoder; the
follower (chunk_follower.py) takes them at CONTROL_HZ. Rates belong to bench/remote_inference.py.
"""

import numpy as np
import pytest
from ai_support import compiled, mock_encoder, node_block

from joshua_core import so100
from testsupport import tiny_act

JOINTS = list(so100.SO100_JOINTS)
CONTROL_HZ = 500.0  # a call of the tiny ACT takes 25 ms or more even on a quiet machine
POLICY_HZ = 30.0
ENCODER_HZ = 50.0
MODEL_CALLS = 6  # chunks to receive after the first
MIN_COMMANDS_PER_CALL = 5
CHUNKS_TIMEOUT_S = 180.0
CHUNKS_TOPIC = "/arm/chunks"
RAW_IMAGE = "sensor_msgs/msg/Image"
COMPRESSED_IMAGE = "sensor_msgs/msg/CompressedImage"  # what a camera sends to another computer


def description(policy_dir, camera_message_type: str) -> dict:
    """Settings of the camera, the arm's encoder ("follower") and the policy publishing chunks."""
    return compiled(
        "MODE_INFERENCE",
        node_block(
            "camera",
            "MOCK_CAMERA_PUBLISHER",
            topic_name=tiny_act.CAMERA_TOPIC,
            message_type=camera_message_type,
            width=tiny_act.WIDTH,
            height=tiny_act.HEIGHT,
            rate_hz=POLICY_HZ,
        ),
        mock_encoder("follower", tiny_act.STATE_TOPIC, JOINTS, ENCODER_HZ),
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


def assert_commands_kept_flowing(record: dict) -> None:
    """The chunks are whole and in order, none was dropped, and the follower executed at least
    MIN_COMMANDS_PER_CALL commands between two chunks and never went a chunk's length without one."""
    arrivals, commands = np.array(record["arrivals"]), np.array(record["commands"])
    first = record["chunks"][0]
    assert first["joint_names"] == JOINTS and len(first["steps_s"]) == tiny_act.CHUNK_SIZE
    assert first["steps_s"] == pytest.approx(np.arange(tiny_act.CHUNK_SIZE) / POLICY_HZ, abs=1e-6)
    # Stamped with the observation's time: before the chunk arrived, after the node started.
    stamps = np.array([chunk["stamp_s"] for chunk in record["chunks"]])
    assert np.all(stamps < arrivals) and np.all(np.diff(stamps) > 0)

    assert record["dropped"] == [""] * len(record["dropped"]), record["dropped"]
    per_call = [np.count_nonzero((commands > a) & (commands <= b)) for a, b in zip(arrivals, arrivals[1:])]
    assert min(per_call) >= MIN_COMMANDS_PER_CALL, per_call
    chunk_length_s = (tiny_act.CHUNK_SIZE - 1) / POLICY_HZ
    in_run = commands[(commands > arrivals[0]) & (commands <= arrivals[-1])]
    assert np.max(np.diff(in_run)) < chunk_length_s, np.max(np.diff(in_run))
