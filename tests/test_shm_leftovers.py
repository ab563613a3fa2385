"""A test run removes, as it ends, the Fast DDS shared-memory files its processes left in /dev/shm
(testsupport/shm_leftovers.py): those created during the run whose lock nobody holds, and no others."""

import fcntl
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.process  # pytest in a process of its own
ROOT = Path(__file__).resolve().parent.parent
SHM = Path("/dev/shm")
# One test leaves a segment whose lock nobody holds (as a killed process would), and one whose lock this
# test holds (as a live process does).
TESTS = """
import time
from pathlib import Path

def test_leaves_segments():
    for name in ("{dead}", "{live}"):
        (Path("/dev/shm") / name).write_bytes(b"\\0" * 4096)
        (Path("/dev/shm") / (name + "_el")).write_text("")
    Path("{signal}").write_text("")
    while Path("{signal}").exists():
        time.sleep(0.01)
"""


def test_files_a_dead_process_left_go_and_those_of_a_live_one_stay(tmp_path):
    dead, live = (f"fastrtps_leftover{os.getpid()}{kind}" for kind in ("dead", "live"))
    signal = tmp_path / "made"
    (tmp_path / "test_leaves.py").write_text(TESTS.format(dead=dead, live=live, signal=signal))
    (tmp_path / "conftest.py").write_text('pytest_plugins = ["testsupport.shm_leftovers"]\n')
    run = subprocess.Popen(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "--rootdir", str(tmp_path),
         str(tmp_path / "test_leaves.py")],
        cwd=tmp_path, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        while not signal.exists():
            assert run.poll() is None, run.stdout.read()
            time.sleep(0.01)
        with open(SHM / f"{live}_el") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            signal.unlink()
            output, _ = run.communicate(timeout=120)
            assert run.returncode == 0, output
            assert "removed 2 Fast DDS shared-memory files" in output, output
            assert not (SHM / dead).exists() and not (SHM / f"{dead}_el").exists()
            assert (SHM / live).exists() and (SHM / f"{live}_el").exists()
    finally:
        run.kill()
        run.wait()
        for name in (dead, live):
            for path in (SHM / name, SHM / f"{name}_el"):
                path.unlink(missing_ok=True)
