"""The runtime's ROS-free tests pass on every other Python the runtime supports that this machine has.

The runtime runs on Python 3.10-3.12 (runtime/pyproject.toml): 3.11 with the ROS 2 wheels of PyPI, which
exist for CPython 3.11 on x86_64 only, and any of them with ROS from the system (`ros_from_system`: apt's
Jazzy on Ubuntu 24.04 is 3.12's). The development environment is 3.11's, so the rest of the suite tests
that one. Here each other interpreter found (testsupport/interpreters.py) gets a fresh environment of
joshua-core, joshua-runtime and joshuac from this checkout with the versions uv.lock holds for that Python,
and no ROS at all; the tests of the drivers, emulators, unit conversions, bench tools, dashboard server and
fleet view run in it, each module in a pytest process of its own. rclpy on 3.12 and aarch64 are not tested here (docs/across-computers.md).
"""

import os
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from testsupport.interpreters import (
    DEVELOPMENT,
    RUNTIME_SUPPORTED,
    install_runtime,
    supported_interpreters,
    with_shared_bytecode,
)
from testsupport.joshuac_cli import ROOT

OTHER_PYTHONS = {v: path for v, path in supported_interpreters(RUNTIME_SUPPORTED).items() if v != DEVELOPMENT}
# What the modules below import besides the runtime's own dependencies: the dashboard and fleet view, the
# LEGO hub's Bluetooth link, MuJoCo (the URDF's kinematics are checked against the simulation's model).
EXTRAS = ("dashboard", "lego", "sim")
GROUPS = ("runtime-tests",)  # pytest and what the modules use of it (pyproject.toml)
ROS_FREE_TESTS = (
    "runtime/tests/servo/test_protocol.py",
    "runtime/tests/servo/test_driver.py",
    "runtime/tests/servo/test_emulator.py",
    "runtime/tests/servo/test_emulator_timing.py",
    "runtime/tests/servo/test_emulator_process.py",
    "runtime/tests/servo/test_calibration.py",
    "runtime/tests/servo/test_command_guard.py",
    "runtime/tests/servo/test_servo_diagnostics.py",
    "runtime/tests/servo/test_servo_tools.py",
    "runtime/tests/servo/test_calibration_rehearsal.py",
    "runtime/tests/sensors/test_lds01_driver.py",
    "runtime/tests/lego/test_pybricks_protocol.py",
    "runtime/tests/lego/test_pybricks_driver.py",
    "runtime/tests/lego/test_odometry.py",
    "runtime/tests/description/test_so100_urdf.py",
    "runtime/tests/dashboard/test_dashboard_server.py",
    "runtime/tests/dashboard/test_dashboard_guards.py",
    "runtime/tests/dashboard/test_dashboard_timeouts.py",
    "runtime/tests/dashboard/test_control_client_owner.py",
    "runtime/tests/dashboard/test_fleet_access.py",
    "runtime/tests/dashboard/test_fleet_schema_roster.py",
    "runtime/tests/dashboard/test_fleet_robot_settings.py",
    "runtime/tests/dashboard/test_fleet_hostile_peers.py",
)
MODULE_TIMEOUT_S = 600  # one module's tests in a subprocess; the longest takes about a minute on a busy machine
MODULES_AT_ONCE = 3  # more made the machine busy enough for a servo scan's 10 ms sweep to miss a reply
# Making an environment (from uv's cache, else PyPI) and running one module in it.
TEST_TIMEOUT_S = 1200


@pytest.fixture(scope="module")
def runtime_environments(tmp_path_factory):
    """runtime_environments(version) -> bin/ of that Python's fresh environment, made once per module."""
    made: dict[str, Path] = {}

    def environment(version: str) -> Path:
        if version not in made:
            venv = tmp_path_factory.mktemp(f"python{version}") / "venv"
            made[version] = install_runtime(OTHER_PYTHONS[version], venv, EXTRAS, GROUPS)
        return made[version]

    return environment


def _environment_variables(bin_dir: Path) -> dict:
    """That environment first on PATH, its bytecode shared by the modules' processes (131 CPU-s for the
    modules on 3.12 when each compiled all it imported, 56 with it shared)."""
    env = {key: value for key, value in os.environ.items() if key not in ("VIRTUAL_ENV", "PYTHONPATH")}
    env["PATH"] = f"{bin_dir}:{env['PATH']}"
    return with_shared_bytecode(env, bin_dir.parent / "bytecode")


@pytest.mark.timeout(TEST_TIMEOUT_S)
@pytest.mark.parametrize("version", sorted(OTHER_PYTHONS))
def test_the_environment_is_that_python_without_ros(version, runtime_environments):
    bin_dir = runtime_environments(version)
    code = (
        "import sys, importlib.util, joshua_runtime\n"
        "print('%d.%d' % sys.version_info[:2], importlib.util.find_spec('rclpy'), joshua_runtime.__file__)\n"
    )
    result = subprocess.run([str(bin_dir / "python"), "-c", code], capture_output=True, text=True, cwd="/")
    assert result.returncode == 0, result.stderr
    python, rclpy, runtime = result.stdout.split()
    assert (python, rclpy) == (version, "None")
    assert runtime.startswith(str(bin_dir.parent)), runtime  # the installed wheel, not this checkout


@pytest.mark.timeout(TEST_TIMEOUT_S)
@pytest.mark.parametrize("version", sorted(OTHER_PYTHONS))
def test_ros_free_tests_pass(version, runtime_environments):
    """Each listed module passes in a pytest process of its own; several run at once, since they mostly wait
    (on timeouts, sockets and subprocesses: about one CPU-second a module)."""
    bin_dir = runtime_environments(version)
    with ThreadPoolExecutor(MODULES_AT_ONCE) as pool:
        failures = [f for f in pool.map(lambda module: _module_failure(bin_dir, module), ROS_FREE_TESTS) if f]
    assert failures == [], f"Python {version}:\n" + "\n".join(failures)


def _module_failure(bin_dir: Path, module: str) -> str | None:
    """Why `module` failed in that Python's pytest (None when it passed)."""
    result = subprocess.run(
        [str(bin_dir / "python"), "-m", "pytest", "-q", "-p", "no:cacheprovider", module],
        cwd=ROOT,
        env=_environment_variables(bin_dir),
        capture_output=True,
        text=True,
        timeout=MODULE_TIMEOUT_S,
    )
    summary = result.stdout.splitlines()[-1] if result.stdout else ""
    if result.returncode == 0 and " passed" in summary:
        return None
    return f"{module} exited {result.returncode}:\n{result.stdout[-6000:]}{result.stderr[-2000:]}"


def test_each_listed_module_exists():
    assert [m for m in ROS_FREE_TESTS if not (ROOT / m).is_file()] == []
