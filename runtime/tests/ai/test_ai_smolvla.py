"""SmolVLA offline: LeRobot's own SmolVLA on a small backbone made here, trained, checked as data and served.

The policy of testsupport/tiny_smolvla.py (trained once per session on demonstrations of two tasks)
loads from a copy in another directory with the Hub offline, follows its instruction, and is served by
an INFERENCE node that takes the episode's task from `/<node>/task`.
"""

import json
import shutil
import signal

import numpy as np
import pytest
from ai_support import NodeProcess, compiled, mock_camera, mock_encoder, node_block
from sensor_msgs.msg import JointState

from joshua_core import so100
from joshua_runtime.ai import data_only, model_files
from joshua_runtime.errors import SettingsError
from testsupport import tiny_act, tiny_smolvla

JOINTS = list(so100.SO100_JOINTS)
ACTION_TOPIC = "/arm/command"
ACTIONS_TIMEOUT_S = 180.0
ACTIONS_WANTED = 3
TASK_QOS = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}


def moved_copy(policy, tmp_path):
    """The policy copied elsewhere, as a registry import or a move to the robot would place it."""
    copy = tmp_path / "elsewhere" / "smolvla"
    shutil.copytree(policy, copy)
    return copy


def test_the_saved_smolvla_holds_its_backbone_and_its_training_tasks(trained_smolvla):
    backbone = trained_smolvla / model_files.SMOLVLA_BACKBONE
    assert {"config.json", "tokenizer.json", "tokenizer_config.json"} <= {p.name for p in backbone.iterdir()}
    config = json.loads((trained_smolvla / "config.json").read_text())
    assert config["type"] == "smolvla" and config["vlm_model_name"] == str(backbone)
    metadata = json.loads((trained_smolvla / "joshua_policy.json").read_text())
    assert metadata["policy_type"] == "smolvla" and metadata["tasks"] == list(tiny_smolvla.TASKS)
    assert len(metadata["loss"]) == tiny_smolvla.TRAINING_STEPS
    data_only.check(trained_smolvla)


def test_a_moved_smolvla_loads_offline_and_follows_its_instruction(trained_smolvla, tmp_path, lerobot_offline):
    import torch

    from joshua_runtime.ai.policy_runner import PolicyRunner

    runner = PolicyRunner(moved_copy(trained_smolvla, tmp_path), "cpu")
    assert runner.config.vlm_model_name == str(tmp_path / "elsewhere" / "smolvla" / model_files.SMOLVLA_BACKBONE)
    assert runner.shapes.images == {"observation.images.camera": (3, tiny_smolvla.HEIGHT, tiny_smolvla.WIDTH)}
    observation = {
        "observation.images.camera": tiny_act.frame_image(0.5, tiny_smolvla.WIDTH, tiny_smolvla.HEIGHT),
        "observation.state": tiny_act.pose(0.5).astype(np.float32),
    }

    def action(task):
        runner.reset()
        torch.manual_seed(0)  # SmolVLA samples its actions from noise
        return runner.act(observation, task)

    first, again, other = action(tiny_smolvla.TASKS[0]), action(tiny_smolvla.TASKS[0]), action(tiny_smolvla.TASKS[1])
    assert first.shape == (len(JOINTS),) and np.all(np.isfinite(first))
    np.testing.assert_array_equal(first, again)
    assert np.max(np.abs(first - other)) > 1e-4, "the instruction does not reach the model"
    chunk = runner.act_chunk(observation, tiny_smolvla.TASKS[0])
    assert chunk.shape == (tiny_smolvla.CHUNK_SIZE, len(JOINTS))


def test_a_backbone_or_tokenizer_outside_the_policy_is_refused(trained_smolvla, tmp_path):
    copy = moved_copy(trained_smolvla, tmp_path)
    outside = tmp_path / "outside_vlm"
    (copy / model_files.SMOLVLA_BACKBONE).rename(outside)
    with pytest.raises(SettingsError, match=r"policy_preprocessor.json: step \d \(its tokenizer\) is '.*'"):
        data_only.check(copy)
    preprocessor = copy / "policy_preprocessor.json"
    pipeline = json.loads(preprocessor.read_text())
    for step in pipeline["steps"]:
        if step["registry_name"] == model_files.TOKENIZER_STEP:
            step["config"]["tokenizer_name"] = "HuggingFaceTB/SmolVLM2-500M-Video-Instruct"
    preprocessor.write_text(json.dumps(pipeline))
    with pytest.raises(
        SettingsError, match="smolvla/config.json: vlm_model_name is '.*/pretrained_model/vlm': neither"
    ):
        data_only.check(copy)


def description(policy_dir) -> dict:
    return compiled(
        "MODE_INFERENCE",
        mock_camera("camera", tiny_act.CAMERA_TOPIC, tiny_smolvla.WIDTH, tiny_smolvla.HEIGHT, 10.0),
        mock_encoder("follower", tiny_act.STATE_TOPIC, JOINTS, 20.0),
        node_block(
            "policy",
            "INFERENCE",
            topic_name=ACTION_TOPIC,
            model_path=str(policy_dir),
            policy_type="smolvla",
            input_topics=[tiny_act.CAMERA_TOPIC, tiny_act.STATE_TOPIC],
            rate_hz=5.0,
        ),
    )


@pytest.mark.timeout(600)
def test_served_smolvla_acts_once_it_has_the_episode_task(trained_smolvla, tmp_path, ai_env, ros_peer):
    from std_msgs.msg import String

    settings = description(moved_copy(trained_smolvla, tmp_path))
    actions = []
    ros_peer.node.create_subscription(JointState, ACTION_TOPIC, actions.append, 10)
    nodes = [NodeProcess(settings[name], ai_env) for name in ("camera", "follower", "policy")]
    try:
        nodes[2].wait_for(r"ready: smolvla policy", timeout=ACTIONS_TIMEOUT_S)
        # Trained on two tasks, it has no instruction of its own: it waits for one and says where to send it.
        nodes[2].wait_for(r"no action: .*no instruction yet: publish one on /policy/task")
        assert actions == []
        publisher = ros_peer.publisher("/policy/task", String, TASK_QOS)
        publisher.publish(String(data=tiny_smolvla.TASKS[1]))
        nodes[2].wait_for(f"instruction: '{tiny_smolvla.TASKS[1]}'")
        received = ros_peer.spin_until(lambda: len(actions) >= ACTIONS_WANTED, ACTIONS_TIMEOUT_S)
        assert received, nodes[2].output
        assert list(actions[0].name) == JOINTS and len(actions[0].position) == len(JOINTS)
        assert np.all(np.isfinite(actions[-1].position))
        for node in nodes:
            assert node.stop(signal.SIGINT) == 0, node.output
    finally:
        for node in nodes:
            node.kill()
