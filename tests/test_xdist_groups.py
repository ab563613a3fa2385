"""The tests of an xdist_group run on one worker of `make test` (testsupport/xdist_groups.py), whether the group
is written on the test or given by testsupport/tiers.py."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.process  # pytest with two xdist workers
ROOT = Path(__file__).resolve().parent.parent
GROUPED = """
import pytest

@pytest.mark.xdist_group("together")
@pytest.mark.parametrize("n", range(4))
def test_written(n):
    pass

@pytest.fixture(scope="module")
def made_once():
    return object()

@pytest.mark.parametrize("n", range(4))
def test_module_fixture(n, made_once):
    pass
"""


def test_tests_of_a_group_share_a_worker(tmp_path):
    (tmp_path / "test_grouped.py").write_text(GROUPED)
    (tmp_path / "conftest.py").write_text('pytest_plugins = ["testsupport.tiers", "testsupport.xdist_groups"]\n')
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "2", "--dist", "loadgroup", "-v",
         "-m", "unit or not unit", "--rootdir", str(tmp_path), str(tmp_path / "test_grouped.py")],
        cwd=tmp_path, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, capture_output=True, text=True,
        timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    workers = {}
    for worker, test in re.findall(r"\[(gw\d)\] \[ *\d+%\] PASSED \S+::(test_\w+)", done.stdout):
        workers.setdefault(test, set()).add(worker)
    assert set(workers) == {"test_written", "test_module_fixture"}, done.stdout[-3000:]
    assert all(len(used) == 1 for used in workers.values()), workers


def test_a_pytest_run_a_worker_starts_without_xdist_is_left_alone(tmp_path):
    """A test's own pytest run inherits the worker's PYTEST_XDIST_WORKER; there xdist may not be installed."""
    (tmp_path / "test_grouped.py").write_text(GROUPED)
    (tmp_path / "conftest.py").write_text('pytest_plugins = ["testsupport.tiers", "testsupport.xdist_groups"]\n')
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-p", "no:xdist", "-q", "-m", "unit or not unit",
         "--rootdir", str(tmp_path), str(tmp_path / "test_grouped.py")],
        cwd=tmp_path, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "PYTEST_XDIST_WORKER": "gw0"},
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "8 passed" in done.stdout
