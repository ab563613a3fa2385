"""Which Fast DDS files count as abandoned: unlocked, created since a moment, with their segment present."""

import fcntl
import time

from joshua_codegen.supervisor import shm
from joshua_codegen.supervisor.policy import SHM_CLOCK_SLACK_S


def segment(directory, name: str) -> None:
    (directory / name).write_bytes(b"\0" * 64)
    (directory / f"{name}_el").write_text("")


def test_only_unlocked_segments_created_since_the_moment_are_removed(tmp_path, monkeypatch):
    monkeypatch.setattr(shm, "SHM_DIR", str(tmp_path))
    segment(tmp_path, "fastrtps_old")  # abandoned too, but before the moment
    time.sleep(4 * SHM_CLOCK_SLACK_S)
    # File times come from the kernel's coarse clock, up to a tick behind time.time(): the slack the
    # supervisor allows for it, or a file created right after `since` may seem older.
    since = time.time() - SHM_CLOCK_SLACK_S
    segment(tmp_path, "fastrtps_dead")
    segment(tmp_path, "fastrtps_port7411")
    (tmp_path / "sem.fastrtps_port7411_mutex").write_bytes(b"\0" * 32)
    segment(tmp_path, "fastrtps_live")
    (tmp_path / "fastrtps_lockonly_el").write_text("")  # no segment: being created, or not ours to judge
    (tmp_path / "other_el").write_text("")
    with open(tmp_path / "fastrtps_live_el") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        assert shm.abandoned_segments(since) == ["fastrtps_dead", "fastrtps_port7411"]
        assert shm.remove_abandoned_segments(since) == (5, 64 + 64 + 32)
        assert sorted(path.name for path in tmp_path.iterdir()) == [
            "fastrtps_live",
            "fastrtps_live_el",
            "fastrtps_lockonly_el",
            "fastrtps_old",
            "fastrtps_old_el",
            "other_el",
        ]
