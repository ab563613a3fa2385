"""pytest --cpu-durations=N (testsupport/cpu_durations.py) ranks tests by the CPU they and the processes they
waited for used, in pytest's own process and across xdist workers alike, and sums it by test directory."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.process  # pytest in a process of its own, with and without xdist workers
ROOT = Path(__file__).resolve().parent.parent
BURN_S = 0.6  # CPU a child of the busy test spends
# One test whose child process burns CPU, one that sleeps as long, one that does nothing.
TESTS = f"""
import subprocess, sys, time

def test_busy_child():
    subprocess.run([sys.executable, "-c", "import time\\nend = time.process_time() + {BURN_S}\\n"
                    "while time.process_time() < end: pass"], check=True)

def test_sleeper():
    time.sleep({BURN_S})

def test_idle():
    pass
"""
ROW = re.compile(r"^\s*(\d+\.\d) CPU-s\s+\d+\.\d %  (\S+)$", re.MULTILINE)


@pytest.mark.parametrize("workers", [[], ["-n", "2"]], ids=["in-process", "xdist"])
def test_the_test_whose_child_burns_cpu_comes_first_with_that_cpu(tmp_path, workers):
    (tmp_path / "test_cpu.py").write_text(TESTS)
    (tmp_path / "conftest.py").write_text('pytest_plugins = ["testsupport.cpu_durations"]\n')
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *workers, "--cpu-durations=2",
         "--rootdir", str(tmp_path), str(tmp_path / "test_cpu.py")],
        cwd=tmp_path, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, capture_output=True, text=True,
        timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "most CPU: 2 of 3 tests" in done.stdout, done.stdout
    rows = [(float(seconds), nodeid) for seconds, nodeid in ROW.findall(done.stdout)]
    tests, directories = rows[:2], rows[2:]
    assert tests[0][1] == "test_cpu.py::test_busy_child" and tests[0][0] >= BURN_S, done.stdout
    assert tests[1][0] < BURN_S / 3, done.stdout  # sleeping costs no CPU
    assert [name for _, name in directories] == ["./"], done.stdout
    assert directories[0][0] >= tests[0][0], done.stdout
