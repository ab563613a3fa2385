"""pytest --cpu-durations=N: the N tests that cost the most CPU, as --durations lists the slowest by wall time.

A test's CPU is its process's (every thread) and that of the processes it started and waited for, with
theirs in turn, from its setup to the end of its teardown (module fixtures count in the test that made or
ended them). Processes nobody of the test waited for (a container's, a daemon's) are not in it. Works in
pytest-xdist workers: each test's figure travels to the controller in its teardown report.
"""

import resource
from collections import defaultdict
from pathlib import PurePosixPath

import pytest

PROPERTY = "cpu_s"
STARTED = pytest.StashKey[float]()
DIRECTORIES_SHOWN = 12


def pytest_addoption(parser):
    parser.getgroup("terminal reporting").addoption(
        "--cpu-durations",
        type=int,
        default=None,
        metavar="N",
        help="show the N tests that cost the most CPU, and the CPU of each test directory (0: every test)",
    )


def cpu_s() -> float:
    """User and system CPU seconds of this process and of the children it has waited for."""
    total = 0.0
    for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN):
        usage = resource.getrusage(who)
        total += usage.ru_utime + usage.ru_stime
    return total


def pytest_configure(config):
    if config.getoption("cpu_durations") is not None and not hasattr(config, "workerinput"):
        config.pluginmanager.register(CpuReport(config.getoption("cpu_durations")), "cpu-durations-report")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    if item.config.getoption("cpu_durations") is not None:
        item.stash[STARTED] = cpu_s()
    yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    if call.when == "teardown" and STARTED in item.stash:
        outcome.get_result().user_properties.append((PROPERTY, cpu_s() - item.stash[STARTED]))


class CpuReport:
    """Collects every test's CPU (from this process's reports or the workers') and prints the summary."""

    def __init__(self, count: int):
        self.count = count
        self.cpu_s: dict[str, float] = {}

    def pytest_runtest_logreport(self, report):
        if report.when == "teardown":
            for name, value in report.user_properties:
                if name == PROPERTY:
                    self.cpu_s[report.nodeid] = value

    def pytest_terminal_summary(self, terminalreporter):
        if not self.cpu_s:
            return
        ranked = sorted(self.cpu_s.items(), key=lambda item: item[1], reverse=True)
        total = sum(self.cpu_s.values())
        percent = 100 / total if total > 0 else 0.0
        shown = ranked if self.count == 0 else ranked[: self.count]
        terminalreporter.write_sep("=", f"most CPU: {len(shown)} of {len(ranked)} tests, {total:.0f} CPU-s in all")
        for nodeid, seconds in shown:
            terminalreporter.write_line(f"{seconds:8.1f} CPU-s {seconds * percent:5.1f} %  {nodeid}")
        by_directory: dict[str, float] = defaultdict(float)
        for nodeid, seconds in ranked:
            by_directory[str(PurePosixPath(nodeid.split("::")[0]).parent)] += seconds
        terminalreporter.write_sep("-", "CPU by test directory")
        for directory, seconds in sorted(by_directory.items(), key=lambda item: item[1], reverse=True)[
            :DIRECTORIES_SHOWN
        ]:
            terminalreporter.write_line(f"{seconds:8.1f} CPU-s {seconds * percent:5.1f} %  {directory}/")
