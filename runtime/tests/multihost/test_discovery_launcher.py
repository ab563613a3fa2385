"""`python -m joshua_runtime.discovery.server`: the wheels' fast-discovery-server, started with its libraries found."""

import subprocess
import sys

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
