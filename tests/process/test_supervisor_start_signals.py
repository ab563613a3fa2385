"""A stop that comes while things start ends them cleanly. A Python node's interpreter in its start: the supervisor
execs it with the stop signals held, and its entrypoint takes them where it can end on them, so nothing prints
Python's fatal error. The supervisor in its preflight: it ends with 0, nothing started, no traceback."""

import os
import re
from pathlib import Path

import pytest
from supervisor_harness import Supervisor, build, robot, wait_until

from joshua_codegen.supervisor.preflight import RUNTIME_PROBE

NODES = ['node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader" rate_hz: 20 }']
START_WAIT_S = 30.0  # an interpreter starting on a machine the whole suite shares
SITE_HOLD_S = 1.5  # how long the node's interpreter stays in its start (importing `site`) once the stop is sent
# A sitecustomize that keeps an interpreter in its start (site's import) until the test has stopped the robot, when
# its command line ends with `{argv_end}`: it says where it is in a file, then waits for the stop's mark.
SLOW_SITE = """
import os, sys, time

if sys.orig_argv[-1].endswith({argv_end!r}):
    with open({inside!r}, "w") as inside:
        inside.write(str(os.getpid()))
    while not os.path.exists({stopped!r}):
        time.sleep(0.01)
    time.sleep({hold})
"""
FATAL_START = ("Fatal Python error", "Traceback", "KeyboardInterrupt")


def stopped_in_start(tmp_path: Path, ros_env: dict, argv_end: str, *options: str) -> tuple[int, Supervisor]:
    """The supervisor's exit code and the Supervisor, stopped with SIGINT while the interpreter whose command line
    ends with `argv_end` is in its start."""
    hooks, inside, stopped = tmp_path / "hooks", tmp_path / "inside-site", tmp_path / "stopped"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(
        SLOW_SITE.format(argv_end=argv_end, inside=str(inside), stopped=str(stopped), hold=SITE_HOLD_S)
    )
    env = dict(ros_env, PYTHONPATH=os.pathsep.join(filter(None, [str(hooks), ros_env.get("PYTHONPATH")])))
    out = build(tmp_path, robot(NODES, sigint=SITE_HOLD_S + 10, sigterm=3))
    supervisor = Supervisor(out, "--no-control", "--log-dir", str(tmp_path / "logs"), *options, env=env)
    try:
        wait_until(inside.exists, f"the interpreter of {argv_end} in its start", timeout=START_WAIT_S)
        supervisor.signal()
        stopped.touch()
        return supervisor.wait(timeout=SITE_HOLD_S + 30), supervisor
    finally:
        supervisor.close()


@pytest.mark.parametrize("options", [(), ("--no-cgroup",)], ids=["cgroup", "tracking"])
def test_a_stop_while_a_python_node_starts_its_interpreter_ends_it_with_0_and_no_fatal_error(
    tmp_path, ros_env, options
):
    code, supervisor = stopped_in_start(tmp_path, ros_env, "leader.py", "--no-node-starter", *options)
    node_output = node_log(tmp_path / "logs", "leader")
    assert not any(text in node_output for text in FATAL_START), node_output
    assert code == 0, supervisor.log()
    assert re.search(r"leader: pid \d+ exited with code 0", supervisor.log()), supervisor.log()


def test_a_stop_during_the_preflight_ends_the_supervisor_with_0_and_starts_nothing(tmp_path, ros_env):
    code, supervisor = stopped_in_start(tmp_path, ros_env, RUNTIME_PROBE)
    assert code == 0, supervisor.log()
    assert "received SIGINT before any node started: nothing was started" in supervisor.log()
    assert not any(text in supervisor.log() for text in FATAL_START + ("started pid",)), supervisor.log()


def node_log(logs: Path, name: str) -> str:
    return "".join(path.read_text(errors="replace") for path in sorted(logs.glob(f"{name}*")))
