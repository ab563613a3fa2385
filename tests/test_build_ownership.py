"""`joshuac build -o OUT` replaces only what it proved it wrote, and cleans up after killed builds."""

import fcntl
import hashlib
import os
import signal
import subprocess
import time

import pytest

from testsupport.joshuac_cli import JOSHUAC, ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line

CONFIG = ROOT / "config/robots/mock_arm.pbtxt"


def snapshot(directory):
    """Every entry under a directory with its bytes (files), target (links) and mode: byte-for-byte state."""
    state = {}
    for path in sorted(directory.rglob("*")):
        status = path.lstat()
        if path.is_symlink():
            content = ("link", os.readlink(path))
        elif path.is_file():
            content = ("file", path.read_bytes())
        else:
            content = ("dir", None)
        state[path.relative_to(directory).as_posix()] = (content, status.st_mode)
    return state


def test_a_directory_holding_a_manifest_and_a_user_file_is_left_byte_for_byte(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "manifest.json").write_text("{}\n")
    (out / "notes.txt").write_text("mine")
    before = snapshot(out)
    result = joshuac("build", CONFIG, "-o", out)
    assert result.returncode == 1
    assert "holds no .joshuac-stamp" in result.stderr and "notes.txt" in result.stderr
    assert snapshot(out) == before


def test_a_description_kept_inside_the_output_survives_the_next_build(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    description = out / "robot.pbtxt"
    description.write_text(CONFIG.read_text())
    before = snapshot(out)
    result = joshuac("build", description, "-o", out)
    assert result.returncode == 1
    assert "files joshuac did not write: robot.pbtxt" in result.stderr
    assert snapshot(out) == before


def test_the_description_directory_itself_is_never_an_output(tmp_path):
    description = tmp_path / "robot.pbtxt"
    description.write_text(CONFIG.read_text())
    result = joshuac("build", "robot.pbtxt", "-o", ".", cwd=tmp_path)
    assert result.returncode == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.pbtxt"]


def test_an_edited_generated_file_is_named_and_kept(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    entrypoint = out / "nodes" / "camera.py"
    entrypoint.write_text(entrypoint.read_text() + "# tuned by hand\n")
    before = snapshot(out)
    result = joshuac("build", CONFIG, "-o", out)
    assert result.returncode == 1
    assert "generated files edited since the last build: nodes/camera.py" in result.stderr
    assert snapshot(out) == before


def test_a_symbolic_link_as_output_is_refused(tmp_path):
    target = tmp_path / "real"
    assert joshuac("build", CONFIG, "-o", target).returncode == 0
    link = tmp_path / "link"
    link.symlink_to(target)
    before = snapshot(tmp_path)
    result = joshuac("build", CONFIG, "-o", link)
    assert result.returncode == 1
    assert "is a symbolic link" in result.stderr
    assert snapshot(tmp_path) == before


def test_a_symbolic_link_inside_the_output_is_not_followed_or_replaced(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    (tmp_path / "data").mkdir()
    (out / "data").symlink_to(tmp_path / "data")
    before = snapshot(tmp_path)
    result = joshuac("build", CONFIG, "-o", out)
    assert result.returncode == 1
    assert "files joshuac did not write: data" in result.stderr
    assert snapshot(tmp_path) == before


def test_the_stamp_lists_every_written_file_with_its_sha256(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    lines = (out / ".joshuac-stamp").read_text().splitlines()
    assert lines[0].startswith("# joshuac ")  # the version line, which sha256sum -c skips
    lines = lines[1:]
    listed = dict(reversed(line.split("  ", 1)) for line in lines)
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()} - {".joshuac-stamp"}
    assert set(listed) == written
    for name, digest in listed.items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest
    assert joshuac("build", CONFIG, "-o", out).returncode == 0  # its own output is replaced


def test_stale_staging_directories_are_removed_and_other_dot_directories_kept(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    stale = tmp_path / ".out.k1ll3d42"
    (stale / "nodes").mkdir(parents=True)
    (stale / ".joshuac-stamp").write_text((out / ".joshuac-stamp").read_text())
    (stale / "nodes" / "camera.py").write_text("# half writ")
    empty = tmp_path / ".out.emptyXYZ"
    empty.mkdir()
    old = tmp_path / ".out.old.ab_12345"
    old.mkdir()
    (old / ".joshuac-stamp").write_text("")
    users = tmp_path / ".out.mystuff1"
    users.mkdir()
    (users / "keep.txt").write_text("mine")
    other = tmp_path / ".other.k1ll3d42"
    other.mkdir()
    busy = tmp_path / ".out.busy1234"
    busy.mkdir()
    held = os.open(busy, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(held, fcntl.LOCK_EX)
    try:
        assert joshuac("build", CONFIG, "-o", out).returncode == 0
    finally:
        os.close(held)
    assert sorted(p.name for p in tmp_path.iterdir()) == [".other.k1ll3d42", ".out.busy1234", ".out.mystuff1", "out"]
    assert (users / "keep.txt").read_text() == "mine"


def test_builds_killed_at_any_moment_leave_nothing_behind_after_the_next_build(tmp_path):
    out = tmp_path / "out"
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    for delay in (0.15, 0.25, 0.35, 0.45):
        process = subprocess.Popen(
            [*JOSHUAC, "build", str(CONFIG), "-o", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
        time.sleep(delay)
        process.send_signal(signal.SIGKILL)
        process.wait()
    result = joshuac("build", CONFIG, "-o", out)
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert joshuac("build", CONFIG, "-o", out, "--check").returncode == 0


def test_an_empty_output_directory_is_used(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    assert joshuac("build", CONFIG, "-o", out).returncode == 0
    assert (out / ".joshuac-stamp").is_file()


def test_concurrent_builds_of_one_output_all_succeed_and_leave_one_tree(tmp_path):
    out = tmp_path / "out"
    builds = [
        subprocess.Popen([*JOSHUAC, "build", str(CONFIG), "-o", str(out)], stderr=subprocess.PIPE, text=True)
        for _ in range(6)
    ]
    failures = [process.stderr.read() for process in builds if process.wait() != 0]
    assert failures == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert joshuac("build", CONFIG, "-o", out, "--check").returncode == 0


def test_a_staging_directory_taken_by_a_concurrent_cleanup_before_its_lock_is_replaced(tmp_path, monkeypatch):
    """Between mkdtemp and flock the new directory is empty and unlocked, so another build may remove it."""
    import tempfile

    from joshua_codegen import write

    made, mkdtemp = [], tempfile.mkdtemp

    def mkdtemp_then_lose_the_first(**kwargs):
        path = mkdtemp(**kwargs)
        made.append(path)
        if len(made) == 1:
            write.remove_stale_staging(tmp_path / "out")  # what a concurrent build does at that moment
        return path

    monkeypatch.setattr(write.tempfile, "mkdtemp", mkdtemp_then_lose_the_first)
    write.write_tree({"a.txt": "a\n"}, tmp_path / "out")
    assert len(made) == 2 and (tmp_path / "out/a.txt").read_text() == "a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_previous_tree_removed_while_a_cleanup_inspects_it_is_skipped(tmp_path, monkeypatch):
    """After an exchange, a build removes the previous tree unlocked; another build's cleanup may be reading it."""
    import shutil

    from joshua_codegen import ownership

    previous = tmp_path / ".out.abcdefgh"
    previous.mkdir()
    (previous / "a.txt").write_text("a\n")
    (previous / "b.txt").write_text("b\n")
    (previous / ownership.STAMP).write_text(ownership.stamp_text({"a.txt": "a\n", "b.txt": "b\n"}))
    entries = ownership._entries

    def entries_while_its_owner_removes_it(directory):
        for number, entry in enumerate(entries(directory)):
            if number == 0:
                shutil.rmtree(directory)
            yield entry

    monkeypatch.setattr(ownership, "_entries", entries_while_its_owner_removes_it)
    ownership.remove_stale_staging(tmp_path / "out")
    assert not previous.exists()
