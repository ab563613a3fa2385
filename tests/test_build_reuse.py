"""A rebuild takes over the files of the previous build that it holds unchanged (a hard link, no new inode),
and never shares a file with anything outside its output."""

import os
import stat

import pytest

from testsupport.joshuac_cli import ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line

CONFIG = ROOT / "config/robots/mock_arm.pbtxt"


def files_of(directory):
    """{relative path: lstat} of every file under a directory."""
    return {p.relative_to(directory).as_posix(): p.lstat() for p in sorted(directory.rglob("*")) if p.is_file()}


def test_a_rebuild_keeps_the_inode_of_every_unchanged_file_and_writes_the_changed_ones(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    before = files_of(out)
    result = joshuac("build", CONFIG, "-o", out, "--set", "camera.rate_hz=30")
    assert result.returncode == 0, result.stderr
    after = files_of(out)
    assert set(after) == set(before)
    changed = {"nodes/camera.py", ".joshuac-stamp"}  # the manifest holds no rates
    kept = set(before) - changed
    assert {name for name in kept if after[name].st_ino == before[name].st_ino} == kept
    assert all(after[name].st_ino != before[name].st_ino for name in changed)
    assert "rate_hz': 30.0" in (out / "nodes/camera.py").read_text()
    assert all(status.st_nlink == 1 for status in after.values())  # the previous tree is gone
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert joshuac("build", CONFIG, "-o", out, "--set", "camera.rate_hz=30", "--check").returncode == 0


def test_a_generated_file_linked_elsewhere_is_written_anew_and_the_other_name_keeps_its_bytes(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    backup = tmp_path / "camera-backup.py"
    os.link(out / "nodes/camera.py", backup)
    kept = backup.read_bytes()
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    assert (out / "nodes/camera.py").stat().st_ino != backup.stat().st_ino
    assert backup.read_bytes() == kept and backup.stat().st_nlink == 1


def test_a_generated_file_whose_mode_was_changed_gets_its_mode_back_in_a_new_file(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    entrypoint = out / "nodes/camera.py"
    entrypoint.chmod(0o700)
    previous = entrypoint.stat().st_ino
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    assert stat.S_IMODE(entrypoint.stat().st_mode) == 0o755
    assert entrypoint.stat().st_ino != previous
    assert joshuac("build", CONFIG, "-o", out, "--check").returncode == 0
