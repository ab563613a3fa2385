"""The workspace's wheels are kept in the user's cache by the digest of their sources and are the wheels uv builds."""

import os
import time
from pathlib import Path

import pytest

from joshua_codegen import bundle, wheel_cache


@pytest.fixture
def cache_home(tmp_path, monkeypatch):
    home = tmp_path / "cache"
    monkeypatch.setenv("XDG_CACHE_HOME", str(home))
    bundle.wheels.cache_clear()
    yield home / wheel_cache.CACHE_DIR
    bundle.wheels.cache_clear()


def member(tmp_path):
    root = tmp_path / "core"
    (root / "joshua_core" / "__pycache__").mkdir(parents=True)
    (root / "pyproject.toml").write_text('[project]\nname = "joshua-core"\n')
    (root / "joshua_core" / "a.py").write_text("A = 1\n")
    return root


def test_the_digest_follows_every_source_but_not_bytecode(tmp_path):
    root = member(tmp_path)
    first = wheel_cache.sources_digest([root])
    (root / "joshua_core" / "__pycache__" / "a.cpython-311.pyc").write_bytes(b"bytecode")
    assert wheel_cache.sources_digest([root]) == first
    changes = [
        lambda: (root / "joshua_core" / "a.py").write_text("A = 2\n"),
        lambda: (root / "joshua_core" / "a.py").chmod(0o755),
        lambda: (root / "joshua_core" / "b.py").write_text(""),
        lambda: (root / "README.md").write_text("the long description\n"),
    ]
    seen = {first}
    for change in changes:
        change()
        digest = wheel_cache.sources_digest([root])
        assert digest not in seen
        seen.add(digest)


def test_kept_wheels_are_loaded_and_only_the_newest_states_stay(cache_home):
    for number in range(wheel_cache.KEPT):
        wheel_cache.store(f"state{number}", {"joshua_core-0.1.0-py3-none-any.whl": b"%d" % number})
        os.utime(cache_home / f"state{number}", (number, number))  # oldest first
    assert wheel_cache.load("state0") == {"joshua_core-0.1.0-py3-none-any.whl": b"0"}  # used: now the newest
    abandoned = cache_home / ".state9-half-written"
    abandoned.mkdir()
    old = time.time() - wheel_cache.ABANDONED_AFTER_S - 1
    os.utime(abandoned, (old, old))
    wheel_cache.store("new", {"joshua_core-0.1.0-py3-none-any.whl": b"new"})
    assert sorted(path.name for path in cache_home.iterdir()) == ["new", "state0", "state2", "state3"]
    assert wheel_cache.load("state1") is None


def test_a_cache_that_cannot_be_written_keeps_nothing_and_fails_nothing(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "file"))
    wheel_cache.store("state", {"joshua_core-0.1.0-py3-none-any.whl": b"wheel"})
    assert wheel_cache.load("state") is None


def test_the_wheels_are_taken_from_the_cache_when_their_sources_are_unchanged(cache_home):
    digest = wheel_cache.sources_digest([bundle.SOURCE_ROOT / member for member in bundle.PACKAGES.values()])
    wheel_cache.store(digest, {"joshua_core-0.1.0-py3-none-any.whl": b"kept"})
    assert bundle.wheels() == {"joshua_core-0.1.0-py3-none-any.whl": b"kept"}


@pytest.mark.process  # uv builds the wheels, twice
def test_kept_wheels_are_those_uv_builds_again(cache_home):
    built = bundle.wheels()  # an empty cache: uv builds them, and they are kept
    assert sorted(built) == ["joshua_core-0.1.0-py3-none-any.whl", "joshua_runtime-0.1.0-py3-none-any.whl"]
    bundle.wheels.cache_clear()
    assert bundle.wheels() == built
    for entry in cache_home.iterdir():
        for wheel in entry.iterdir():
            wheel.unlink()  # nothing kept: uv builds them again, byte for byte as before
    bundle.wheels.cache_clear()
    assert bundle.wheels() == built


def test_wheels_built_while_a_source_changed_are_not_kept(cache_home, monkeypatch):
    digests = iter(["before", "after"])
    monkeypatch.setattr(wheel_cache, "sources_digest", lambda members: next(digests))

    def build(*arguments):  # `uv build ... --out-dir DIR`: one wheel in DIR
        out_dir = Path(arguments[arguments.index("--out-dir") + 1])
        (out_dir / f"{arguments[arguments.index('--package') + 1]}-0.1.0-py3-none-any.whl").write_bytes(b"wheel")

    monkeypatch.setattr(bundle, "uv", build)
    assert sorted(bundle.wheels()) == ["joshua-core-0.1.0-py3-none-any.whl", "joshua-runtime-0.1.0-py3-none-any.whl"]
    assert not cache_home.exists()
