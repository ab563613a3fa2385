"""How long the test tiers take: `make test-fast` and `make test`, each against its target on a 2-core machine.

    .venv/bin/python bench/suite.py                 # both, fast tier first
    .venv/bin/python bench/suite.py --only fast     # or --only full

Not run by the test suite (it runs the suite). "wall" is what a developer waits; "cpu" the user+system
seconds of make and everything it started, which other load on the machine changes little. The load
average before and after says how busy the machine was: figures taken at a load above the core count are
not the machine's own. Each make runs as it would by hand (setup included); a failing run is reported too.
After `make test` come the tests that cost the most CPU and the CPU of each test directory (pytest's
--cpu-durations, testsupport/cpu_durations.py): where the suite's time goes.
"""

import argparse
import os
import resource
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGETS_S = {"test-fast": 60.0, "test": 360.0}  # on the 2-core machine the suite is written for
MOST_CPU_SHOWN = {"test": 15}  # the tests of a target whose CPU is printed after it
ONLY = {"fast": ("test-fast",), "full": ("test",), "both": ("test-fast", "test")}


def children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed_make(target: str) -> tuple[int, float, float, list[str]]:
    """(exit code, wall seconds, cpu seconds, pytest's output lines) of `make -s TARGET`."""
    env = dict(os.environ)
    if target in MOST_CPU_SHOWN:
        env["PYTEST_ARGS"] = f"{env.get('PYTEST_ARGS', '')} --cpu-durations={MOST_CPU_SHOWN[target]}".strip()
    cpu, started = children_cpu_s(), time.monotonic()
    result = subprocess.run(["make", "-s", target], cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    wall, cpu = time.monotonic() - started, children_cpu_s() - cpu
    lines = [line for line in result.stdout.splitlines() if line.strip()]
    return result.returncode, wall, cpu, (lines or [result.stderr.strip()[-200:]])


def most_cpu(lines: list[str]) -> list[str]:
    """The --cpu-durations summary among pytest's output lines: from its heading to the next "=" heading."""
    start = next((i for i, line in enumerate(lines) if line.startswith("=") and " most CPU: " in line), None)
    if start is None:
        return []
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("==")), len(lines))
    return lines[start:end]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", choices=sorted(ONLY), default="both", help="which tiers to time (default both)")
    args = parser.parse_args()
    print(f"{os.cpu_count()} cores; targets: " + ", ".join(f"make {t} {s:g} s" for t, s in TARGETS_S.items()))
    failed = False
    for target in ONLY[args.only]:
        load = os.getloadavg()[0]
        code, wall, cpu, lines = timed_make(target)
        summary = lines[-1].strip("= ")
        failed |= code != 0
        verdict = "within" if wall <= TARGETS_S[target] else "over"
        print(
            f"make {target}: {wall:.1f} s wall ({wall / TARGETS_S[target]:.2f} of its {TARGETS_S[target]:g} s target, "
            f"{verdict}), {cpu:.1f} CPU-s, load average {load:.1f} -> {os.getloadavg()[0]:.1f}, exit {code}: {summary}"
        )
        for line in most_cpu(lines):
            print(line)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
