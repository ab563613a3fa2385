"""The local model registry and `joshua-registry`: import, list, resolve, revisions, errors."""

import json
import subprocess
import sys

import pytest

from joshua_runtime.ai import model_files, registry
from joshua_runtime.errors import SettingsError


def saved_policy(directory, weights=b"weights", policy_type="act", dataset_root=None):
    """The files LeRobot writes for a policy (contents are not read by the registry)."""
    directory.mkdir(parents=True)
    (directory / "config.json").write_text(json.dumps({"type": policy_type}))
    (directory / "model.safetensors").write_bytes(weights)
    (directory / "policy_preprocessor.json").write_text("{}")
    (directory / "policy_postprocessor.json").write_text("{}")
    if dataset_root is not None:
        train_config = {"dataset": {"repo_id": "local/x", "root": str(dataset_root)}}
        (directory / "train_config.json").write_text(json.dumps(train_config))
    return directory


def dataset_info(root, action_names, state_names):
    (root / "meta").mkdir(parents=True)
    features = {
        "action": {"dtype": "float32", "shape": [len(action_names)], "names": action_names},
        "observation.state": {"dtype": "float32", "shape": [len(state_names)], "names": state_names},
        "observation.images.camera": {"dtype": "video", "shape": [24, 32, 3], "names": ["height", "width", "channels"]},
    }
    (root / "meta" / "info.json").write_text(json.dumps({"features": features}))


@pytest.fixture
def registry_root(tmp_path, monkeypatch):
    monkeypatch.setenv(registry.REGISTRY_ENV, str(tmp_path / "registry"))
    return tmp_path / "registry"


def cli(*args, env_root):
    env = {
        "PATH": "/usr/bin:/bin",
        registry.REGISTRY_ENV: str(env_root),
        "HF_HUB_OFFLINE": "1",
        "HF_HOME": str(env_root.parent / "hf-home"),
    }
    return subprocess.run(
        [sys.executable, "-m", "joshua_runtime.ai.registry_cli", *args],
        env=env,
        capture_output=True,
        text=True,
    )


def test_import_resolves_latest_and_explicit_revisions(tmp_path, registry_root):
    first = registry.import_policy(saved_policy(tmp_path / "a", b"one"), "arm")
    second = registry.import_policy(saved_policy(tmp_path / "b", b"two"), "arm", revision="v2")
    assert len(first.revision) == registry.DIGEST_LENGTH and first.path == registry_root / "arm" / first.revision
    assert (first.sequence, second.sequence) == (1, 2)
    assert registry.resolve("registry:arm") == second
    assert registry.resolve(f"registry:arm@{first.revision}") == first
    assert (first.path / "model.safetensors").read_bytes() == b"one"
    assert [e.revision for e in registry.entries()] == [first.revision, "v2"]
    # The same files again: nothing new, the existing entry is returned.
    assert registry.import_policy(tmp_path / "a", "arm") == first
    with pytest.raises(registry.RegistryError, match="arm@v2 already exists with different files"):
        registry.import_policy(tmp_path / "a", "arm", revision="v2")


def test_training_output_directory_and_feature_names_are_kept(tmp_path, registry_root):
    dataset = tmp_path / "dataset"
    dataset_info(dataset, ["shoulder_pan.pos", "gripper.pos"], ["a.pos", "b.pos"])
    training = tmp_path / "train"
    saved_policy(training / "checkpoints" / "last" / "pretrained_model", dataset_root=dataset)
    entry = registry.import_policy(training, "arm")
    assert entry.path.name == entry.revision and (entry.path / "config.json").is_file()
    dataset.joinpath("meta", "info.json").unlink()  # the entry no longer needs the dataset
    assert model_files.feature_names(entry.path) == {
        "action": ["shoulder_pan.pos", "gripper.pos"],
        "observation.state": ["a.pos", "b.pos"],
    }


def test_errors_name_the_problem(tmp_path, registry_root):
    with pytest.raises(registry.RegistryError, match=r"registry:ghost is not in the registry at .*registry"):
        registry.resolve("registry:ghost")
    with pytest.raises(registry.RegistryError, match="invalid model name 'a/b'"):
        registry.import_policy(saved_policy(tmp_path / "p"), "a/b")
    with pytest.raises(registry.RegistryError, match="invalid revision 'x y'"):
        registry.parse_reference("registry:arm@x y")
    not_a_policy = tmp_path / "empty"
    not_a_policy.mkdir()
    with pytest.raises(SettingsError, match="no LeRobot policy"):
        registry.import_policy(not_a_policy, "arm")
    partial = tmp_path / "partial"
    partial.mkdir()
    (partial / "config.json").write_text('{"type": "act"}')
    with pytest.raises(SettingsError, match="lacks model.safetensors, policy_preprocessor.json"):
        registry.import_policy(partial, "arm")


def test_command_line(tmp_path):
    root = tmp_path / "registry"
    policy = saved_policy(tmp_path / "policy", policy_type="diffusion")
    added = cli("import", str(policy), "--name", "pusher", "--revision", "r1", env_root=root)
    assert added.returncode == 0 and added.stdout == f"pusher@r1 (diffusion) -> {root / 'pusher' / 'r1'}\n"
    resolved = cli("resolve", "registry:pusher", env_root=root)
    assert (resolved.returncode, resolved.stdout) == (0, f"{root / 'pusher' / 'r1'}\n")
    listed = cli("list", env_root=root)
    assert listed.returncode == 0
    assert listed.stdout.splitlines()[1].split()[:3] == ["pusher", "r1*", "diffusion"]
    missing = cli("resolve", "pusher@r9", env_root=root)
    assert (missing.returncode, missing.stderr) == (
        1,
        f"joshua-registry: error: registry:pusher@r9 is not in the registry at {root}\n",
    )
    assert cli("import", str(policy), env_root=root).returncode == 2  # --name is required
    removed = cli("remove", "pusher@r1", env_root=root)
    assert (removed.returncode, removed.stdout) == (0, "removed pusher@r1\n")
    assert cli("list", env_root=root).stdout == f"no models in {root}\n"
    offline = cli("pull", "some-org/some-policy", env_root=root)  # the Hub is used only by pull
    assert offline.returncode == 1
    assert offline.stderr.startswith(
        "joshua-registry: error: cannot download some-org/some-policy from the Hugging Face Hub: "
    )
    assert len(offline.stderr.splitlines()) == 1


def test_resolution_never_touches_the_network(tmp_path, registry_root, monkeypatch):
    import socket

    def refuse(*args, **kwargs):
        raise AssertionError("network access")

    monkeypatch.setattr(socket, "create_connection", refuse)
    monkeypatch.setattr(socket.socket, "connect", refuse)
    entry = registry.import_policy(saved_policy(tmp_path / "p"), "arm")
    assert registry.resolve("registry:arm").path == entry.path
