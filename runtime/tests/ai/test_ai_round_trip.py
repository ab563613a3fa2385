"""Record from mock sensors, train a tiny ACT with LeRobot's training script, serve it, watch actions."""

import signal
import subprocess
import sys
import time

import numpy as np
from ai_support import (
    LINE_TIMEOUT_S,
    RELIABLE,
    NodeProcess,
    compiled,
    mock_camera,
    mock_encoder,
    node_block,
    pattern_image,
)
from sensor_msgs.msg import Image, JointState
from std_msgs.msg import String

from joshua_core import so100

SO100_JOINTS = list(so100.SO100_JOINTS)
HEIGHT, WIDTH = 24, 32
SENSOR_HZ = 30.0
RECORD_HZ = 10.0
INFERENCE_HZ = 20.0
EPISODE_S = 1.0
TRAIN_TIMEOUT_S = 300
ACTIONS_TO_COMPARE = 3
ACTIONS_TOPIC = "/rt/arm/commands"
# Tiny ACT: small transformer, no pretrained backbone (nothing is downloaded), one action per inference.
TINY_ACT = [
    "--policy.type=act",
    "--policy.device=cpu",
    "--policy.push_to_hub=false",
    "--policy.pretrained_backbone_weights=null",
    "--policy.dim_model=32",
    "--policy.n_heads=2",
    "--policy.dim_feedforward=64",
    "--policy.n_encoder_layers=1",
    "--policy.n_vae_encoder_layers=1",
    "--policy.chunk_size=4",
    "--policy.n_action_steps=1",
]


def recording_settings(output) -> dict[str, dict]:
    return compiled(
        "MODE_DATA_COLLECTION",
        mock_camera("rt_camera", "/rt/camera/image_raw", WIDTH, HEIGHT, SENSOR_HZ),
        mock_encoder("rt_leader", "/rt/leader/joint_states", SO100_JOINTS, SENSOR_HZ),
        mock_encoder("rt_follower", "/rt/follower/joint_states", SO100_JOINTS, SENSOR_HZ),
        node_block(
            "rt_recorder",
            "DATA_SUBSCRIBER",
            topic_name="/rt/leader/joint_states",
            input_topics=["/rt/camera/image_raw", "/rt/follower/joint_states"],
            output_directory=str(output),
            rate_hz=RECORD_HZ,
        ),
    )


def inference_settings() -> dict:
    """The INFERENCE node of a robot with the same sensors (published by this test in that phase)."""
    return compiled(
        "MODE_INFERENCE",
        mock_camera("rt_camera", "/rt/camera/image_raw", WIDTH, HEIGHT, SENSOR_HZ),
        mock_encoder("rt_follower", "/rt/follower/joint_states", SO100_JOINTS, SENSOR_HZ),
        node_block(
            "rt_policy",
            "INFERENCE",
            topic_name=ACTIONS_TOPIC,
            model_path="registry:tiny_act",
            input_topics=["/rt/camera/image_raw", "/rt/follower/joint_states"],
            policy_type="act",
            rate_hz=INFERENCE_HZ,
        ),
    )["rt_policy"]


def record(tmp_path, env, ros_peer):
    """Two episodes of the mock camera and encoders, recorded by a DATA_SUBSCRIBER process."""
    output = tmp_path / "dataset"
    settings = recording_settings(output)
    commands = ros_peer.publisher("/rt_recorder/episode", String, RELIABLE)
    sensors = [NodeProcess(settings[name], env) for name in ("rt_camera", "rt_leader", "rt_follower")]
    recorder = NodeProcess(settings["rt_recorder"], env)
    try:
        recorder.wait_for("first frame of the episode recorded")
        time.sleep(EPISODE_S)
        mark = recorder.count()
        ros_peer.send_text(commands, "stop")
        recorder.wait_for(r"episode 0 saved", after=mark)
        ros_peer.send_text(commands, "start")
        recorder.wait_for("first frame of the episode recorded", after=mark)
        time.sleep(EPISODE_S)
        assert recorder.stop(signal.SIGINT) == 0
        recorder.wait_for(r"episode 1 saved", after=mark)
    finally:
        for process in [recorder, *sensors]:
            if process.process.poll() is None:
                process.stop(signal.SIGINT)
    return output


def train(tmp_path, env, dataset):
    output = tmp_path / "train"
    command = [
        sys.executable,
        "-m",
        "lerobot.scripts.lerobot_train",
        "--dataset.repo_id=local/round_trip",
        f"--dataset.root={dataset}",
        "--dataset.video_backend=pyav",
        *TINY_ACT,
        "--steps=2",
        "--batch_size=2",
        "--num_workers=0",
        "--save_freq=2",
        "--log_freq=1",
        "--wandb.enable=false",
        f"--output_dir={output}",
    ]
    result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=TRAIN_TIMEOUT_S)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return output


def in_process_action(policy_dir, observation):
    """LeRobot's own inference path on `observation`, independent of the node's code."""
    import torch
    from lerobot.configs.policies import PreTrainedConfig
    from lerobot.policies.act.modeling_act import ACTPolicy
    from lerobot.policies.factory import make_pre_post_processors
    from lerobot.utils.control_utils import predict_action

    config = PreTrainedConfig.from_pretrained(policy_dir)
    policy = ACTPolicy.from_pretrained(policy_dir, config=config)
    preprocessor, postprocessor = make_pre_post_processors(config, pretrained_path=str(policy_dir))
    action = predict_action(dict(observation), policy, torch.device("cpu"), preprocessor, postprocessor, False)
    return action.squeeze(0).numpy()


def test_record_train_serve_round_trip(tmp_path, ai_env, ros_peer, lerobot_offline, monkeypatch):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    from joshua_runtime.ai.ros_arrays import joint_state, rgb_to_image

    dataset_root = record(tmp_path, ai_env, ros_peer)
    dataset = LeRobotDataset("local/round_trip", root=dataset_root, video_backend="pyav")
    assert dataset.meta.total_episodes == 2 and len(dataset) >= 2
    assert dataset.meta.features["action"]["names"] == [f"{j}.pos" for j in SO100_JOINTS]

    training = train(tmp_path, ai_env, dataset_root)
    imported = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.ai.registry_cli", "import", str(training), "--name", "tiny_act"],
        env=ai_env,
        capture_output=True,
        text=True,
    )
    assert imported.returncode == 0, imported.stderr
    policy_dir = imported.stdout.strip().rsplit(" -> ", 1)[1]

    # A constant observation; the state is published with its joints in another order than the policy's.
    image = pattern_image(HEIGHT, WIDTH, 90)
    state = np.linspace(-0.5, 0.5, len(SO100_JOINTS)).astype(np.float32)
    shuffled = list(reversed(range(len(SO100_JOINTS))))
    camera = ros_peer.publish_periodically("/rt/camera/image_raw", Image, SENSOR_HZ, lambda: rgb_to_image(image))
    ros_peer.publish_periodically(
        "/rt/follower/joint_states",
        JointState,
        SENSOR_HZ,
        lambda: joint_state([SO100_JOINTS[i] for i in shuffled], state[shuffled]),
    )
    ros_peer.listen(ACTIONS_TOPIC, JointState, RELIABLE, keep=ACTIONS_TO_COMPARE)
    settings = inference_settings()
    node = NodeProcess(settings, ai_env)
    try:
        node.wait_for(r"ready: act policy from .*tiny_act.* on cpu")
        assert ros_peer.spin_until(lambda: ros_peer.count(ACTIONS_TOPIC) >= ACTIONS_TO_COMPARE, LINE_TIMEOUT_S), (
            f"no {ACTIONS_TO_COMPARE} actions on {ACTIONS_TOPIC}"
        )
        actions = ros_peer.messages(ACTIONS_TOPIC)
        # LeRobot's config loading leaves a copy of config.json in the temporary directory: the test's own.
        monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
        expected = in_process_action(policy_dir, {"observation.images.rt_camera": image, "observation.state": state})
        for message in actions:
            assert list(message.name) == SO100_JOINTS
            np.testing.assert_allclose(np.array(message.position), expected, rtol=1e-5, atol=1e-5)

        camera.cancel()  # stale camera: no more actions
        mark = node.count()
        node.wait_for(r"no action: /rt/camera/image_raw is stale", after=mark)
        time.sleep(0.2)  # let actions already sent arrive
        silent_from = ros_peer.count(ACTIONS_TOPIC)
        time.sleep(0.5)
        assert ros_peer.count(ACTIONS_TOPIC) == silent_from
        assert node.stop(signal.SIGINT) == 0
    finally:
        node.kill()
