"""A stop that takes longer than the agents' own bounds, asked with `ctl --host` on a robot on two hosts: ctl says
how long it waits, and each agent on the way waits as long (less a margin), so the answer comes, not `unreachable`.

The node stops as the recorder does while it saves: it asks its supervisor for more time until it is done."""

import pytest

from joshua_runtime.dashboard.control_client import REQUEST_TIMEOUT_S
from joshua_runtime.hosts.link import QUERY_TIMEOUT_S
from testsupport.slow_stopper import slow_stopper_node
from testsupport.split_robot import running_split_robot

SAVING_S = max(QUERY_TIMEOUT_S, REQUEST_TIMEOUT_S) + 2.0  # longer than an agent waits for a request without a wait
EXTENSION_S = 5.0  # asked for every second while it saves


@pytest.fixture(scope="module")
def robot(tmp_path_factory, request):
    directory = tmp_path_factory.mktemp("split")
    saver = slow_stopper_node(directory, "saver", EXTENSION_S, 1.0, SAVING_S, "exit", 'host: "arm"')
    with running_split_robot(directory, request.node.nodeid, more_nodes=saver) as robot:
        yield robot


def saver_events(robot) -> list[str]:
    log = robot.directory / "events.log"
    return [line.split(" ", 2)[2] for line in log.read_text().splitlines()] if log.exists() else []


@pytest.mark.parametrize("asked_on", ["gpu", "arm"])  # over Zenoh to the other host's agent; through its own
def test_ctl_host_stop_is_answered_once_a_slow_node_has_saved(robot, asked_on):
    if robot.node("arm", "saver")["state"] == "stopped":  # by the test before; left stopped, the robot stops at once
        started = robot.ctl(asked_on, "--host", "arm", "start", "saver")
        assert started.returncode == 0, started
    robot.wait_until(lambda: saver_events(robot)[-1:] == ["start"], "the saver started")

    stopped = robot.ctl(asked_on, "--host", "arm", "stop", "saver")

    assert stopped.returncode == 0 and stopped.stdout.strip() == "saver: stopped", (stopped, robot.logs())
    assert saver_events(robot)[-2:] == ["got SIGINT saving", "saved"]  # it saved for SAVING_S, unescalated
    assert robot.node("arm", "saver")["state"] == "stopped"
