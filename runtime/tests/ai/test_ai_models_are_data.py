"""Models are data, never code: the registry and the INFERENCE node refuse pickles, links and code in processors.

Every crafted payload writes a marker file when it runs; the marker must never appear, whether the
model is imported, served by a node process or loaded by the policy runner.
"""

import hashlib
import json
import os
import pickle
import struct
import subprocess
import sys

import numpy as np
import pytest
from ai_support import NodeProcess, compiled, mock_encoder, node_block, save_tiny_diffusion

from joshua_runtime.ai import registry
from joshua_runtime.errors import JoshuaError, SettingsError
from testsupport import crafted_models

ARM_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex"]
NODE_EXIT_TIMEOUT_S = 120


def lerobot_files(directory, policy_type="act"):
    """The files LeRobot saves for a policy, with a valid (empty) safetensors file and processor pipelines."""
    directory.mkdir(parents=True)
    (directory / "config.json").write_text(json.dumps({"type": policy_type}))
    (directory / "model.safetensors").write_bytes(safetensors_bytes(b"{}"))
    for name in ("policy_preprocessor.json", "policy_postprocessor.json"):
        (directory / name).write_text(json.dumps({"name": name[:-5], "steps": []}))
    return directory


def safetensors_bytes(header: bytes) -> bytes:
    return struct.pack("<Q", len(header)) + header


@pytest.fixture
def registry_root(tmp_path, monkeypatch):
    monkeypatch.setenv(registry.REGISTRY_ENV, str(tmp_path / "registry"))
    return tmp_path / "registry"


def assert_refused(exc_info, path, *words):
    message = str(exc_info.value)
    assert str(path) in message, message
    for word in words:
        assert word in message, message
    assert "\n" not in message


def test_import_refuses_a_pickled_ppo_policy_and_names_the_file(tmp_path, registry_root):
    marker = tmp_path / "unpickled"
    run = crafted_models.pickled_ppo_run(tmp_path / "run", marker)
    with pytest.raises(JoshuaError) as refused:
        registry.import_policy(run, "evil")
    assert_refused(refused, run / "policy.zip", "pickle", "--trust-pickle")
    assert registry.entries() == [] and not marker.exists()


@pytest.mark.parametrize(
    ("name", "content"),
    [
        ("training_args.bin", lambda marker: crafted_models.payload(marker, protocol=2)),
        ("stats", lambda marker: crafted_models.payload(marker, protocol=0)),
        ("optimizer.pt", lambda marker: b"anything"),
        ("normalizer.pkl.gz", lambda marker: b"\x1f\x8b compressed"),
        ("objects.npy", lambda marker: object_array_bytes()),
        ("extras.zip", lambda marker: torch_save_bytes()),
    ],
)
def test_import_refuses_a_lerobot_policy_holding_a_pickle(tmp_path, registry_root, name, content):
    marker = tmp_path / "unpickled"
    policy = lerobot_files(tmp_path / "policy")
    (policy / "assets").mkdir()
    (policy / "assets" / name).write_bytes(content(marker))
    with pytest.raises(JoshuaError) as refused:
        registry.import_policy(policy, "arm")
    assert_refused(refused, policy / "assets" / name, "pickle")
    assert registry.entries() == [] and not marker.exists()


def object_array_bytes() -> bytes:
    import io

    stream = io.BytesIO()
    np.save(stream, np.array([{"a": 1}, None], dtype=object), allow_pickle=True)
    return stream.getvalue()


def torch_save_bytes() -> bytes:
    import io

    import torch

    stream = io.BytesIO()
    torch.save({"weights": torch.zeros(2)}, stream)
    return stream.getvalue()


def test_data_files_that_look_like_pickles_at_first_byte_are_kept(tmp_path, registry_root):
    policy = lerobot_files(tmp_path / "policy")
    # A safetensors header of 640 bytes starts with b"\x80\x02", the opening of a protocol-2 pickle.
    header = json.dumps({"__metadata__": {"note": "x" * 590}}).encode()
    header += b" " * (640 - len(header))
    (policy / "model.safetensors").write_bytes(safetensors_bytes(header))
    assert (policy / "model.safetensors").read_bytes()[:2] == b"\x80\x02"
    np.save(policy / "numbers.npy", np.arange(4.0))
    (policy / "README.md").write_text("N.B. a model card\n")
    entry = registry.import_policy(policy, "arm")
    assert sorted(entry.files) == [
        "README.md",
        "config.json",
        "model.safetensors",
        "numbers.npy",
        "policy_postprocessor.json",
        "policy_preprocessor.json",
    ]


@pytest.mark.parametrize("link", ["file", "directory"])
def test_import_refuses_symbolic_links(tmp_path, registry_root, link):
    secret = tmp_path / "outside" / "secret"
    secret.parent.mkdir()
    secret.write_text("private key\n")
    secret.chmod(0o600)
    policy = lerobot_files(tmp_path / "policy")
    linked = policy / ("notes.txt" if link == "file" else "assets")
    linked.symlink_to(secret if link == "file" else secret.parent)
    with pytest.raises(JoshuaError) as refused:
        registry.import_policy(policy, "arm")
    assert_refused(refused, linked, "symbolic link")
    assert registry.entries() == []
    assert not any(p.name == "secret" for p in registry_root.rglob("*"))


def test_the_digest_covers_every_byte_served(tmp_path, registry_root):
    policy = lerobot_files(tmp_path / "policy")
    (policy / "assets").mkdir()
    (policy / "assets" / "card.json").write_text("{}")
    (policy / "joshua_features.json").write_text(json.dumps({"action": ["a.pos"]}))
    entry = registry.import_policy(policy, "arm")
    served = sorted(
        p.relative_to(entry.path).as_posix()
        for p in entry.path.rglob("*")
        if p.is_file() and p.name != "joshua_model.json"
    )
    assert sorted(entry.files) == served and "joshua_features.json" in served and "assets/card.json" in served
    for name, digest in entry.files.items():
        assert hashlib.sha256((entry.path / name).read_bytes()).hexdigest() == digest
    registry.verify(entry)

    (entry.path / "assets" / "card.json").write_text('{"changed": true}')
    with pytest.raises(registry.RegistryError) as changed:
        registry.verify(registry.resolve("registry:arm"))
    assert_refused(changed, "assets/card.json", "changed after import")


def test_processor_steps_that_name_python_code_are_refused(tmp_path, registry_root):
    marker = tmp_path / "ran"
    policy = lerobot_files(tmp_path / "policy")
    step = {"class": "subprocess.run", "config": {"args": ["touch", str(marker)]}}
    (policy / "policy_preprocessor.json").write_text(json.dumps({"name": "policy_preprocessor", "steps": [step]}))
    with pytest.raises(JoshuaError) as refused:
        registry.import_policy(policy, "arm")
    assert_refused(refused, policy / "policy_preprocessor.json", "subprocess.run")
    assert not marker.exists()


def test_the_policy_runner_refuses_code_in_a_saved_pipeline_before_loading_it(tmp_path, lerobot_offline):
    from joshua_runtime.ai.policy_runner import PolicyRunner

    marker = tmp_path / "ran"
    policy = save_tiny_diffusion(tmp_path / "diffusion", 24, 32, np.zeros(2), np.ones(2))
    pipeline = json.loads((policy / "policy_postprocessor.json").read_text())
    pipeline["steps"].insert(0, {"class": "subprocess.run", "config": {"args": ["touch", str(marker)]}})
    (policy / "policy_postprocessor.json").write_text(json.dumps(pipeline))
    with pytest.raises(SettingsError) as refused:
        PolicyRunner(policy, "cpu")
    assert_refused(refused, policy / "policy_postprocessor.json", "subprocess.run")
    assert not marker.exists()

    pipeline["steps"][0] = {"registry_name": "normalizer_processor", "state_file": "../stats.safetensors"}
    (policy / "policy_postprocessor.json").write_text(json.dumps(pipeline))
    with pytest.raises(SettingsError) as outside:
        PolicyRunner(policy, "cpu")
    assert_refused(outside, policy / "policy_postprocessor.json", "../stats.safetensors")


def test_a_lerobot_policy_loads_and_acts_without_unpickling(tmp_path, lerobot_offline, monkeypatch, temporary):
    from joshua_runtime.ai.policy_runner import PolicyRunner

    policy = save_tiny_diffusion(tmp_path / "diffusion", 24, 32, np.zeros(2), np.ones(2))
    crafted_models.forbid_unpickling(monkeypatch)
    runner = PolicyRunner(policy, "cpu")
    assert runner.warm_up() > 0
    assert list(temporary.iterdir()) == []  # LeRobot's config loading leaves a copy of config.json there


def test_the_allowed_processor_steps_are_those_lerobot_saves_for_act_diffusion_and_smolvla(tmp_path, lerobot_offline):
    from lerobot.configs.types import FeatureType, PolicyFeature
    from lerobot.policies.factory import make_pre_post_processors

    from joshua_runtime.ai.model_files import ALLOWED_PROCESSOR_STEPS, SUPPORTED_POLICY_TYPES
    from joshua_runtime.train import imitation, small_vlm

    features = {
        "input_features": {"observation.state": PolicyFeature(FeatureType.STATE, (2,))},
        "output_features": {"action": PolicyFeature(FeatureType.ACTION, (2,))},
    }
    vlm = small_vlm.write(tmp_path / "vlm")
    saved = set()
    for policy_type in SUPPORTED_POLICY_TYPES:
        config = imitation.policy_config(policy_type, vlm=vlm)
        config.input_features, config.output_features = features["input_features"], features["output_features"]
        assert config.type == policy_type
        for pipeline in make_pre_post_processors(config, dataset_stats=None):
            saved.update(type(step)._registry_name for step in pipeline.steps)
    assert sorted(saved) == sorted(ALLOWED_PROCESSOR_STEPS)


def inference_settings(model_path) -> dict:
    return compiled(
        "MODE_INFERENCE",
        mock_encoder("evil_arm", "/evil/arm/state", ARM_JOINTS, 30.0),
        node_block(
            "evil_policy",
            "INFERENCE",
            topic_name="/evil/arm/command",
            model_path=str(model_path),
            input_topics=["/evil/arm/state"],
            rate_hz=20.0,
        ),
    )["evil_policy"]


def node_errors(settings: dict, env: dict) -> tuple[int, list[str]]:
    node = NodeProcess(settings, env)
    try:
        code = node.process.wait(timeout=NODE_EXIT_TIMEOUT_S)
        node._reader.join()
    finally:
        node.kill()
    assert not any("Traceback" in line for line in node.lines), node.output
    return code, [line for line in node.lines if "error" in line]


def test_a_node_serving_a_pickled_registry_model_refuses_it(tmp_path, ai_env):
    marker = tmp_path / "unpickled"
    run = crafted_models.pickled_ppo_run(tmp_path / "run", marker)
    root = tmp_path / "registry"
    entry = crafted_models.planted_registry_entry(root, "evil", "r1", run, "sb3-ppo")
    code, errors = node_errors(inference_settings("registry:evil"), ai_env)
    assert code == 2 and len(errors) == 1, errors
    assert f"evil_policy: error: {entry / 'policy.zip'}" in errors[0] and "pickle" in errors[0]
    assert not marker.exists()


def test_a_node_refuses_a_registry_entry_changed_after_import(tmp_path, ai_env):
    env_root = tmp_path / "registry"
    imported = subprocess.run(
        [
            sys.executable,
            "-m",
            "joshua_runtime.ai.registry_cli",
            "import",
            str(lerobot_files(tmp_path / "p")),
            "--name",
            "arm",
        ],
        env={**os.environ, registry.REGISTRY_ENV: str(env_root)},
        capture_output=True,
        text=True,
    )
    assert imported.returncode == 0, imported.stderr
    entry_dir = next((env_root / "arm").iterdir())
    (entry_dir / "model.safetensors").write_bytes(safetensors_bytes(b'{"x": 1}'))
    code, errors = node_errors(inference_settings("registry:arm"), ai_env)
    assert code == 2
    assert errors == [
        f"evil_policy: error: registry:arm@{entry_dir.name}: model.safetensors changed after import "
        f"(its SHA-256 is not the one in {entry_dir / 'joshua_model.json'}); import the policy again"
    ]


def test_pull_has_no_trust_pickle_option(tmp_path):
    pulled = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.ai.registry_cli", "pull", "org/policy", "--trust-pickle"],
        env={**os.environ, registry.REGISTRY_ENV: str(tmp_path / "registry"), "HF_HUB_OFFLINE": "1"},
        capture_output=True,
        text=True,
    )
    assert pulled.returncode == 2 and "unrecognized arguments: --trust-pickle" in pulled.stderr


def test_pickle_payloads_used_here_really_run_when_unpickled(tmp_path):
    """The crafted files are live: unpickling them writes the marker (so its absence above means something)."""
    marker = tmp_path / "unpickled"
    pickle.loads(crafted_models.payload(marker, protocol=0))
    assert marker.read_text() == "unpickled"
