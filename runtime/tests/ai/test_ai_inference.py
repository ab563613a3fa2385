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


def save_tiny_diffusion(directory):
    """A small untrained Diffusion policy saved with its processors, as LeRobot saves any policy."""
    import torch
    from lerobot.configs.types import FeatureType, PolicyFeature
    from lerobot.policies.diffusion.configuration_diffusion import DiffusionConfig
    from lerobot.policies.diffusion.modeling_diffusion import DiffusionPolicy
    from lerobot.policies.factory import make_pre_post_processors

    config = DiffusionConfig(
        device="cpu",
        push_to_hub=False,
        n_obs_steps=2,
        horizon=8,
        n_action_steps=2,
        drop_n_last_frames=5,
        down_dims=(16, 32),
        n_groups=4,
        diffusion_step_embed_dim=16,
        spatial_softmax_num_keypoints=8,
        num_inference_steps=2,
        input_features={
            "observation.images.camera": PolicyFeature(FeatureType.VISUAL, (3, HEIGHT, WIDTH)),
            "observation.state": PolicyFeature(FeatureType.STATE, (2,)),
        },
        output_features={"action": PolicyFeature(FeatureType.ACTION, (2,))},
    )

    def stats(low, high, shape):
        low, high = torch.tensor(low, dtype=torch.float32), torch.tensor(high, dtype=torch.float32)
        return {
            "min": low.reshape(shape),
            "max": high.reshape(shape),
            "mean": ((low + high) / 2).reshape(shape),
            "std": ((high - low) / 4).reshape(shape),
        }

    dataset_stats = {
        "observation.images.camera": stats([0.0] * 3, [1.0] * 3, (3, 1, 1)),
        "observation.state": stats([-2.0, -2.0], [2.0, 2.0], (2,)),
        "action": stats(ACTION_MIN.tolist(), ACTION_MAX.tolist(), (2,)),
    }
    torch.manual_seed(0)
    policy = DiffusionPolicy(config)
    preprocessor, postprocessor = make_pre_post_processors(config, dataset_stats=dataset_stats)
    policy.save_pretrained(directory)
    preprocessor.save_pretrained(directory)
    postprocessor.save_pretrained(directory)
    # What `joshua-registry import` keeps from the training dataset: the action names.
    (directory / "joshua_features.json").write_text(json.dumps({"action": ["wrist.pos", "gripper.pos"]}))
    return directory


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

    policy_dir = save_tiny_diffusion(tmp_path / "diffusion")
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
        ("unsupported", "inf_policy: error: policy type 'pi0' is not supported (supported: act, diffusion, sb3-ppo)"),
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
