"""Fixtures of the AI tests: an offline environment for LeRobot, shared bytecode, a ROS peer."""

import importlib.util
import os
import sys
from pathlib import Path

import pytest
from ai_support import RosPeer

from testsupport.interpreters import with_shared_bytecode

OFFLINE = {"HF_HUB_OFFLINE": "1", "HF_DATASETS_OFFLINE": "1", "TRANSFORMERS_OFFLINE": "1"}


def installed_bytecode() -> bool:
    """Whether LeRobot was installed with its compiled bytecode."""
    spec = importlib.util.find_spec("lerobot")
    return bool(spec and spec.origin) and Path(importlib.util.cache_from_source(spec.origin)).exists()


@pytest.fixture(scope="session")
def bytecode_cache(request, tmp_path_factory):
    """A bytecode cache kept across runs in pytest's cache directory, or None when not needed.

    When the environment has no compiled bytecode and forbids writing it (PYTHONDONTWRITEBYTECODE),
    every process compiles torch and LeRobot from source (over ten seconds each); node processes and
    this one then share compiled modules here.
    """
    if installed_bytecode() or not sys.flags.dont_write_bytecode:
        return None
    cache = getattr(request.config, "cache", None)
    directory = cache.mkdir("joshua-ai-bytecode") if cache is not None else tmp_path_factory.mktemp("bytecode")
    sys.pycache_prefix = str(directory)
    sys.dont_write_bytecode = False
    return directory


@pytest.fixture(scope="session")
def lerobot_offline(tmp_path_factory, bytecode_cache):
    """Make this process offline for Hugging Face libraries before any of them is imported."""
    saved = {key: os.environ.get(key) for key in [*OFFLINE, "HF_DATASETS_CACHE", "HF_LEROBOT_HOME"]}
    os.environ.update(OFFLINE)
    os.environ["HF_DATASETS_CACHE"] = str(tmp_path_factory.mktemp("hf-datasets-cache"))
    os.environ["HF_LEROBOT_HOME"] = str(tmp_path_factory.mktemp("lerobot-home"))
    yield
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


@pytest.fixture
def ai_env(ros_env, tmp_path, bytecode_cache) -> dict:
    """Environment of node and tool processes: the test's ROS domain, offline, private caches."""
    env = dict(ros_env)
    env.update(OFFLINE)
    env["HF_DATASETS_CACHE"] = str(tmp_path / "hf-datasets-cache")
    env["HF_LEROBOT_HOME"] = str(tmp_path / "lerobot-home")
    env["JOSHUA_MODEL_REGISTRY"] = str(tmp_path / "registry")
    return env if bytecode_cache is None else with_shared_bytecode(env, bytecode_cache)


@pytest.fixture
def ros_peer(ros_domain):
    """The test's ROS peer (see ai_support.RosPeer) in its ROS domain; closed at teardown."""
    with RosPeer() as peer:
        yield peer


@pytest.fixture(scope="session")
def trained_act(tmp_path_factory, lerobot_offline) -> Path:
    """A real ACT (320x240 camera, chunks of tiny_act.CHUNK_SIZE) trained offline once per session."""
    from testsupport.tiny_act import train_tiny_act

    return train_tiny_act(tmp_path_factory.mktemp("tiny-act"))


@pytest.fixture(scope="session")
def trained_smolvla(tmp_path_factory, lerobot_offline) -> Path:
    """A real SmolVLA (small backbone made offline, two tasks) trained once per session."""
    from testsupport.tiny_smolvla import train_tiny_smolvla

    return train_tiny_smolvla(tmp_path_factory.mktemp("tiny-smolvla"))


@pytest.fixture
def temporary(tmp_path, monkeypatch) -> Path:
    """An empty directory that is this process's TMPDIR (and its children's) for the test."""
    directory = tmp_path / "tmp"
    directory.mkdir()
    monkeypatch.setenv("TMPDIR", str(directory))
    monkeypatch.setattr("tempfile.tempdir", None)  # read TMPDIR again; monkeypatch puts the old value back
    return directory
