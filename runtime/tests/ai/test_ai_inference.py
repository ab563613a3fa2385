"""The INFERENCE node as a real process: a Diffusion policy, missing inputs, unusable settings."""

import json
import signal
import time

import numpy as np
import pytest
from ai_support import (
    IMAGE,
    LINE_TIMEOUT_S,
    RELIABLE,
    NodeProcess,
    compiled,
    mock_camera,
    mock_encoder,
    node_block,
    pattern_image,
    save_tiny_diffusion,
    topic,
)
from sensor_msgs.msg import Image, JointState

HEIGHT, WIDTH = 24, 32
SENSOR_HZ = 30.0
INFERENCE_HZ = 10.0
ACTIONS_TO_CHECK = 3
ACTIONS_TOPIC = "/inf/arm/commands"
ACTION_MIN = np.array([-1.0, 0.0], np.float32)
ACTION_MAX = np.array([1.0, 2.0], np.float32)


def inference_settings(model_path, **fields):
    """The INFERENCE node's settings as joshuac writes them (this test publishes the sensors itself)."""
    return compiled(
        "MODE_INFERENCE",
        mock_camera("inf_camera", "/inf/camera/image_raw", WIDTH, HEIGHT, SENSOR_HZ),
        mock_encoder("inf_arm", "/inf/arm/state", ["wrist", "gripper"], SENSOR_HZ),
        node_block(
            "inf_policy",
            "INFERENCE",
            topic_name=ACTIONS_TOPIC,
            model_path=str(model_path),
            input_topics=["/inf/camera/image_raw", "/inf/arm/state"],
            rate_hz=INFERENCE_HZ,
            **fields,
        ),
    )["inf_policy"]


def test_diffusion_policy_waits_for_every_input_then_publishes_named_actions(
    tmp_path, ai_env, ros_peer, lerobot_offline
):
    from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

    policy_dir = save_tiny_diffusion(tmp_path / "diffusion", HEIGHT, WIDTH, ACTION_MIN, ACTION_MAX)
    image = pattern_image(HEIGHT, WIDTH, 30)
    ros_peer.publish_periodically("/inf/camera/image_raw", Image, SENSOR_HZ, lambda: rgb_to_image(image))
    ros_peer.listen(ACTIONS_TOPIC, JointState, RELIABLE, keep=ACTIONS_TO_CHECK)
    node = NodeProcess(inference_settings(policy_dir, policy_type="diffusion"), ai_env)
    try:
        node.wait_for(r"ready: diffusion policy from .* on cpu")
        mark = node.count()
        node.wait_for(r"no action: /inf/arm/state has not published yet", after=mark)
        time.sleep(1.0 / INFERENCE_HZ * 3)
        assert ros_peer.count(ACTIONS_TOPIC) == 0

        ros_peer.publish_periodically(
            "/inf/arm/state", JointState, SENSOR_HZ, lambda: joint_state(["wrist", "gripper"], [0.1, 0.2])
        )
        assert ros_peer.spin_until(lambda: ros_peer.count(ACTIONS_TOPIC) >= ACTIONS_TO_CHECK, LINE_TIMEOUT_S), (
            f"no {ACTIONS_TO_CHECK} actions on {ACTIONS_TOPIC}"
        )
        for message in ros_peer.messages(ACTIONS_TOPIC):
            assert list(message.name) == ["wrist", "gripper"]
            position = np.array(message.position)
            # Diffusion clips its normalised samples to [-1, 1]: actions stay within the action range.
            assert np.all(position >= ACTION_MIN - 1e-4) and np.all(position <= ACTION_MAX + 1e-4)
        node.wait_for(r"first action published")
        assert node.stop(signal.SIGINT) == 0
    finally:
        node.kill()


def fake_policy(directory, policy_type):
    """The files of a saved policy, enough for the checks done before loading weights."""
    directory.mkdir(parents=True)
    (directory / "config.json").write_text(json.dumps({"type": policy_type}))
    for name in ("model.safetensors", "policy_preprocessor.json", "policy_postprocessor.json"):
        (directory / name).write_text("{}")
    return directory


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("missing", "inf_policy: error: model path {tmp}/missing is not a directory"),
        ("unregistered", "inf_policy: error: registry:nothing is not in the registry at {tmp}/registry"),
        ("mismatch", "inf_policy: error: policy_type is 'diffusion' but the policy in {tmp}/act is 'act'"),
        (
            "unsupported",
            "inf_policy: error: policy type 'pi0' is not supported (supported: act, diffusion, smolvla, sb3-ppo)",
        ),
        ("cuda", "inf_policy: error: device 'cuda' requested but CUDA is not available on this machine"),
        (
            "action_topic",
            "inf_policy: error: inf_policy: the action topic must be sensor_msgs/msg/JointState or "
            "trajectory_msgs/msg/JointTrajectory",
        ),
    ],
)
def test_unusable_settings_exit_2_with_one_line(tmp_path, ai_env, case, message):
    act = fake_policy(tmp_path / "act", "act")
    settings = {
        "missing": lambda: inference_settings(tmp_path / "missing"),
        "unregistered": lambda: inference_settings("registry:nothing"),
        "mismatch": lambda: inference_settings(act, policy_type="diffusion"),
        "unsupported": lambda: inference_settings(fake_policy(tmp_path / "pi0", "pi0")),
        "cuda": lambda: inference_settings(act, device="cuda"),
        "action_topic": lambda: dict(inference_settings(act), topic=topic(ACTIONS_TOPIC, IMAGE)),
    }[case]()
    env = dict(ai_env, CUDA_VISIBLE_DEVICES="")
    node = NodeProcess(settings, env)
    assert node.process.wait(timeout=120) == 2
    node._reader.join()
    errors = [line for line in node.lines if "error" in line]
    assert errors == [message.format(tmp=tmp_path)]
    assert not any("Traceback" in line for line in node.lines)
