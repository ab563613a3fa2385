"""`python -m joshua_runtime.discovery.server`: the wheels' fast-discovery-server, started with its libraries found."""

import signal
import subprocess
import sys

from testsupport.dds_processes import ROOT, SERVER_PORT, SERVER_TYPE_LINE, START_TIMEOUT_S, probe_server_from
from testsupport.dds_profiles import server_profile, write_profile
from testsupport.probe_output import ProbeOutput

LAUNCHER = [sys.executable, "-m", "joshua_runtime.discovery.server"]


def launch(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*LAUNCHER, *args], capture_output=True, text=True, timeout=60)


def test_bad_arguments_get_one_line_and_exit_code_2():
    for args in (["--address", "robot.local"], ["--address", "10.0.0.1", "--port", "0"], []):
        result = launch(*args)
        assert result.returncode == 2, result
        assert "Traceback" not in result.stderr and result.stderr.strip().splitlines()[-1].startswith("python -m")
    missing = launch("--address", "10.0.0.1", "--profile", "/nonexistent/server.xml")
    assert (
        missing.returncode == 2
        and missing.stderr == "error: the server profile /nonexistent/server.xml does not exist\n"
    )


def test_the_server_binary_runs_with_its_libraries_found():
    from joshua_runtime.discovery import server

    result = subprocess.run(
        [str(server.binary_path()), "--help"], env=server.environment({}), capture_output=True, text=True, timeout=60
    )
    assert "cannot open shared object file" not in result.stderr
    assert "--server-id" in result.stdout + result.stderr


def test_the_supervised_server_takes_a_profile_and_serves_in_the_nodes_environment(hosts, ros_env, tmp_path):
    server_xml = tmp_path / "server.xml"
    server_xml.write_text(server_profile())
    client_xml = write_profile(tmp_path / "client.xml", server=(hosts["robot"].address, SERVER_PORT))
    env = dict(ros_env, FASTRTPS_DEFAULT_PROFILES_FILE=str(client_xml))  # as the supervisor hands it to nodes
    command = [
        sys.executable, "-m", "joshua_runtime.discovery.supervised", "--address", hosts["robot"].address,
        "--profile", str(server_xml),
    ]  # fmt: skip
    server = ProbeOutput(hosts["robot"].popen(command, cwd=ROOT, env=env, stdout=subprocess.PIPE, text=True))
    assert server.wait_for(lambda output: any(SERVER_TYPE_LINE in line for line in output.lines()), START_TIMEOUT_S), (
        server.tail()
    )
    assert probe_server_from(hosts["gpu"], hosts["robot"].address).startswith("True")
    server.process.send_signal(signal.SIGINT)
    assert server.process.wait(START_TIMEOUT_S) == 0
