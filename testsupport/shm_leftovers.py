"""The Fast DDS shared-memory files that processes of a test run left in /dev/shm are removed as it ends.

Many tests kill ROS processes on purpose (SIGKILL leaves a process's segments behind: about 70 MB a full
run). At the end of the run (in pytest's own process, after every xdist worker), every segment created
since the run began whose lock no live process holds goes, by the rule the supervisor uses for its nodes
(joshua_codegen/supervisor/shm.py): a live process holds its lock from before the segment exists.
"""

import time

import pytest

from joshua_codegen.supervisor.policy import SHM_CLOCK_SLACK_S
from joshua_codegen.supervisor.shm import remove_abandoned_segments

BEGAN = pytest.StashKey[float]()


def pytest_configure(config):
    config.stash[BEGAN] = time.time()


@pytest.hookimpl(trylast=True)
def pytest_sessionfinish(session):
    if hasattr(session.config, "workerinput"):
        return  # a worker: the run is not over
    files, size = remove_abandoned_segments(session.config.stash[BEGAN] - SHM_CLOCK_SLACK_S)
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if files and reporter is not None:
        reporter.ensure_newline()
        reporter.write_line(
            f"removed {files} Fast DDS shared-memory files ({size / 2**20:.1f} MiB) that processes of the tests left"
        )
