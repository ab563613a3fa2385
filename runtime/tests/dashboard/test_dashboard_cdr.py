"""JointState and Image read from their CDR bytes give the events rclpy's deserialized messages give."""

import random

import numpy as np
import pytest
from rclpy.serialization import deserialize_message, serialize_message
from sensor_msgs.msg import Image, JointState, LaserScan

from joshua_core.message_types import JOINT_STATE, LASER_SCAN
from joshua_runtime.dashboard import cdr, frames

CASES = 200


def random_joint_state(rng: random.Random) -> JointState:
    """Names of every length (each string's padding differs), arrays of different lengths, empty ones."""
    count = rng.randrange(0, 8)
    special = [float("nan"), float("inf"), -float("inf"), -0.0, 1e308, 5e-324]

    def values():
        return [
            rng.choice(special) if rng.random() < 0.1 else rng.uniform(-10, 10) for _ in range(rng.choice([0, count]))
        ]

    message = JointState(
        name=["j" * rng.randrange(0, 9) + "é" * rng.randrange(0, 2) for _ in range(count)],
        position=values(),
        velocity=values(),
        effort=values(),
    )
    message.header.stamp.sec = rng.choice([0, 1, -1, 2**31 - 1, -(2**31), rng.randrange(0, 2**31)])
    message.header.stamp.nanosec = rng.randrange(0, 10**9)
    message.header.frame_id = "f" * rng.randrange(0, 6)
    return message


def random_image(rng: random.Random) -> Image:
    encoding, channels = rng.choice([("rgb8", 3), ("bgr8", 3), ("mono8", 1), ("rgba8", 4), ("bgra8", 4)])
    width, height = rng.randrange(1, 40), rng.randrange(1, 30)
    step = width * channels + rng.choice([0, 0, 1, 3, 8])
    message = Image(
        height=height,
        width=width,
        encoding=encoding,
        step=step,
        is_bigendian=rng.randrange(0, 2),
        data=rng.randbytes(step * height),
    )
    message.header.stamp.sec, message.header.stamp.nanosec = rng.randrange(0, 2**31), rng.randrange(0, 10**9)
    message.header.frame_id = "c" * rng.randrange(0, 7)
    return message


@pytest.mark.parametrize("seed", range(CASES))
def test_joint_state_fields_are_those_rclpy_reads(seed):
    serialized = serialize_message(random_joint_state(random.Random(seed)))
    expected = deserialize_message(serialized, JointState)
    fields = cdr.decode(JOINT_STATE, serialized)
    assert fields.header.stamp == (expected.header.stamp.sec, expected.header.stamp.nanosec)
    assert fields.header.frame_id == expected.header.frame_id
    assert fields.name == expected.name
    for name in ("position", "velocity", "effort"):
        assert np.array_equal(fields[fields._fields.index(name)], getattr(expected, name), equal_nan=True)
    assert frames.joint_state_event("/j", fields) == frames.joint_state_event("/j", expected)


@pytest.mark.parametrize("seed", range(CASES // 4))
def test_image_fields_are_those_rclpy_reads_and_give_the_same_frame(seed):
    serialized = serialize_message(random_image(random.Random(seed)))
    expected = deserialize_message(serialized, Image)
    fields = cdr.decode(cdr.IMAGE, serialized)
    assert fields.header.stamp == (expected.header.stamp.sec, expected.header.stamp.nanosec)
    assert (fields.height, fields.width, fields.encoding, fields.is_bigendian, fields.step) == (
        expected.height,
        expected.width,
        expected.encoding,
        expected.is_bigendian,
        expected.step,
    )
    assert bytes(fields.data) == bytes(expected.data)
    assert frames.image_event("/c", fields) == frames.image_event("/c", expected)


def test_other_types_and_encapsulations_are_left_to_rclpy():
    joints = bytearray(serialize_message(JointState(name=["a"], position=[1.0])))
    assert cdr.decode(LASER_SCAN, bytes(serialize_message(LaserScan()))) is None
    joints[1] = 0  # big-endian CDR
    assert cdr.decode(JOINT_STATE, bytes(joints)) is None
    joints[1] = 7  # XCDR2
    assert cdr.decode(JOINT_STATE, bytes(joints)) is None


def test_a_message_cut_short_is_a_value_error():
    joints = serialize_message(random_joint_state(random.Random(1)))
    image = serialize_message(Image(height=2, width=2, encoding="mono8", step=2, data=bytes(4)))
    for data, message_type in ((joints, JOINT_STATE), (image, cdr.IMAGE)):
        for end in range(2, len(data)):
            with pytest.raises(ValueError):
                cdr.decode(message_type, data[:end])
