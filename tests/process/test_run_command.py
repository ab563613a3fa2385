"""run_supervisor (behind `joshuac run`): the supervisor in the foreground, signals forwarded once."""

import os
import re
import signal
import subprocess
import sys

import pytest
from supervisor_harness import PYTHON, build, custom_node, events, robot, wait_until

from testsupport.joshuac_cli import ROOT

RUNNER = (
    "import sys; from pathlib import Path; from joshua_codegen.run import run_supervisor; "
    "sys.exit(run_supervisor(Path(sys.argv[1]), sys.argv[2:]))"
)
MAKE_TIMEOUT_S = 300  # `make run` sets the machine up first (seconds when it is already)


def run_in_subprocess(out, *args):
    return subprocess.Popen(
        [PYTHON, "-c", RUNNER, str(out), *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )


@pytest.mark.parametrize("number", [signal.SIGINT, signal.SIGTERM])
def test_stop_signals_reach_the_supervisor_once_and_its_exit_code_comes_back(tmp_path, number):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log)]))
    runner = run_in_subprocess(out)
    try:
        wait_until(lambda: events(log), "the node to start")
        runner.send_signal(number)
        output, _ = runner.communicate(timeout=10)
    finally:
        runner.kill()
    assert runner.returncode == 0, output
    assert [text for _, _, text in events(log)] == ["start", "got SIGINT exit"]
    assert f"received {signal.Signals(number).name}: stopping every node" in output
    assert "again" not in output


def test_extra_arguments_and_failure_codes_pass_through(tmp_path):
    out = build(tmp_path, robot(['node { name: "x" type: CUSTOM executable: "joshua-no-such-program" }']))
    runner = run_in_subprocess(out, "--duration", "5")
    output, _ = runner.communicate(timeout=10)
    assert runner.returncode == 3, output


def test_the_supervisor_stops_its_nodes_when_the_runner_is_killed(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log)]))
    runner = run_in_subprocess(out)
    try:
        wait_until(lambda: events(log), "the node to start")
        runner.kill()
        runner.wait()
        wait_until(
            lambda: [text for _, _, text in events(log)] == ["start", "got SIGINT exit"],
            "the node to be stopped with SIGINT",
        )
    finally:
        runner.kill()
        runner.stdout.close()


def test_run_is_a_joshuac_command():
    result = subprocess.run([sys.executable, "-m", "joshua_codegen", "run", "--help"], capture_output=True, text=True)
    assert result.returncode == 0
    assert "--duration" in result.stdout and "--skip-preflight" in result.stdout


@pytest.mark.parametrize("interval", [None, "0.5"], ids=["quiet", "STATUS_INTERVAL"])
def test_make_run_prints_status_lines_only_when_asked(tmp_path, interval):
    config = tmp_path / "quiet.pbtxt"
    config.write_text(robot([custom_node("a", tmp_path / "events.log"), custom_node("b", tmp_path / "events.log")]))
    env = dict(os.environ, XDG_RUNTIME_DIR=str(tmp_path / "run"), XDG_STATE_HOME=str(tmp_path / "state"))
    (tmp_path / "run").mkdir(mode=0o700)
    variables = [f"RUN_CONFIG={config}", "DURATION=3"] + ([f"STATUS_INTERVAL={interval}"] if interval else [])
    result = subprocess.run(
        ["make", "-s", "run", *variables], cwd=ROOT, env=env, capture_output=True, text=True, timeout=MAKE_TIMEOUT_S
    )
    output = result.stdout + result.stderr
    assert result.returncode == 0, output[-3000:]
    status_lines = re.findall(r"supervisor: status: 2 running$", output, re.M)
    if interval is None:
        assert status_lines == [] and "running pid" not in output
    else:
        assert len(status_lines) >= 3
    assert "supervisor: ready: 2 of 2 nodes ready" in output
