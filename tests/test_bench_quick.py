"""Every benchmark in bench/ runs end to end in its quick mode and prints figures, so none can rot.

The figures are the benchmarks' business: only the exit code and that some figure was printed are checked.
bench/suite.py times the test suite itself, so the suite leaves it out.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parent.parent / "bench"
# A quick run takes seconds to a minute alone; this only ends a hang (fleet.py took 285 s under the suite's load).
BENCH_TIMEOUT_S = 600.0
TEARDOWN_S = 30.0  # pytest's own limit for the test: the run's, and its end
FIGURE = re.compile(r"\d+\.\d+")
NOT_IN_THE_SUITE = {"suite.py"}  # runs `make test`

# One benchmark at a time: each loads the machine, and its figures say more without a neighbour.
pytestmark = [
    pytest.mark.bench,
    pytest.mark.process,
    pytest.mark.xdist_group("bench"),
    pytest.mark.timeout(BENCH_TIMEOUT_S + TEARDOWN_S),
]


@pytest.mark.parametrize(
    "script", sorted(path.name for path in BENCH.glob("*.py") if path.name not in NOT_IN_THE_SUITE)
)
def test_bench_quick_mode_runs_and_prints_figures(script, ros_env):
    result = subprocess.run(
        [sys.executable, str(BENCH / script), "--quick"],
        cwd=BENCH,
        env=ros_env,
        capture_output=True,
        text=True,
        timeout=BENCH_TIMEOUT_S,
    )
    assert result.returncode == 0, f"{script} --quick exited {result.returncode}:\n{result.stdout}\n{result.stderr}"
    assert FIGURE.search(result.stdout), f"{script} --quick printed no figure:\n{result.stdout}\n{result.stderr}"
