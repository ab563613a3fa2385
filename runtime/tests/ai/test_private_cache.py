"""A writer's private cache in /tmp is removed by the next one made once its process is gone, even killed."""

import os
import signal
import subprocess
import sys
import time

from joshua_runtime.ai import private_cache

HOLDER = """
import sys, time
from joshua_runtime.ai import private_cache
directory, _lock = private_cache.make(sys.argv[1])
print(directory, flush=True)
time.sleep(600)
"""


def holder(prefix: str, temporary) -> tuple[subprocess.Popen, str]:
    process = subprocess.Popen(
        [sys.executable, "-c", HOLDER, prefix],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "TMPDIR": str(temporary)},
    )
    return process, process.stdout.readline().strip()


def test_the_cache_of_a_killed_process_goes_and_that_of_a_live_one_stays(temporary):
    killed, killed_directory = holder("cache-", temporary)
    live, live_directory = holder("cache-", temporary)
    try:
        killed.send_signal(signal.SIGKILL)
        killed.wait()
        directory, lock = private_cache.make("cache-")
        assert not os.path.exists(killed_directory)
        assert os.path.isdir(live_directory) and os.path.isdir(directory)
        private_cache.remove(directory, lock)
        assert not os.path.exists(directory)
    finally:
        live.kill()
        live.wait()
        killed.stdout.close()
        live.stdout.close()


def test_an_old_directory_without_a_lock_goes_and_a_new_one_stays(temporary):
    old, new = temporary / "cache-old", temporary / "cache-new"
    old.mkdir()
    new.mkdir()
    long_ago = time.time() - private_cache.UNLOCKED_AFTER_S - 1
    os.utime(old, (long_ago, long_ago))
    private_cache.remove_abandoned("cache-")
    assert not old.exists() and new.is_dir()


def test_a_closed_writer_leaves_the_datasets_cache_where_it_was(temporary, monkeypatch, tmp_path):
    """A process that records a dataset and then reads it (a script, `joshua-train demonstrate`, the tests'
    tiny ACT) must not recreate the writer's removed cache: the datasets library is pointed back after close."""
    import datasets.config
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    from joshua_runtime.ai.episode_writer import CACHE_PREFIX
    from testsupport.tiny_act import record_dataset

    monkeypatch.setenv("HF_DATASETS_CACHE", str(tmp_path / "users-cache"))
    monkeypatch.setattr(datasets.config, "HF_DATASETS_CACHE", tmp_path / "users-cache")
    dataset = record_dataset(tmp_path / "dataset", episodes=1, frames=3, size=(16, 12))
    assert os.environ["HF_DATASETS_CACHE"] == str(tmp_path / "users-cache")
    assert datasets.config.HF_DATASETS_CACHE == tmp_path / "users-cache"
    assert len(LeRobotDataset("local/dataset", root=dataset)) == 3
    assert list(temporary.glob(f"{CACHE_PREFIX}*")) == []
