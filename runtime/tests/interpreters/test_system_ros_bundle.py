"""A host with `ros_from_system` installs its bundle on apt's Python, and the runtime works there without ROS wheels.

apt's ROS 2 Jazzy is Ubuntu 24.04's, built for its Python 3.12. This machine has neither, so install.sh runs
in a mount namespace of its own whose /opt holds a stand-in /opt/ros/jazzy/setup.sh (a private tmpfs, so
nothing of this machine's /opt changes), with the host's `python` set to a 3.12 interpreter found here. The
bundle must install (its requirements from uv.lock for 3.12, no ROS wheel), the environment must see the
system's packages, and the runtime's ROS-free tools must work in it: joshua-emulate serves an STS3215 bus that
joshua-servo scans. A host without ros_from_system takes the ROS wheels of PyPI, which exist for Python 3.11
only: install.sh refuses any other Python before it makes anything. rclpy itself on 3.12 (apt's) is not
tested here.
"""

import json
import os
import signal
import subprocess
from pathlib import Path

import pytest
from uv import find_uv_bin

from testsupport.interpreters import RUNTIME_SUPPORTED, supported_interpreters
from testsupport.joshuac_cli import joshuac

APT_JAZZY_PYTHON = "3.12"  # Ubuntu 24.04's, which apt's ROS 2 Jazzy is built for
SYSTEM_PYTHONS = {v: p for v, p in supported_interpreters(RUNTIME_SUPPORTED).items() if v == APT_JAZZY_PYTHON}
ROS_SETUP = Path("/opt/ros/jazzy/setup.sh")  # what install.sh of a ros_from_system host sources
SOURCED = "stand-in for apt's ROS 2 Jazzy: setup.sh sourced"
INSTALL_TIMEOUT_S = 600
TOOL_TIMEOUT_S = 60
DESCRIPTION = """
robot_config {{
  name: "apt_arm"
  mode: MODE_TELEOPERATION
  host {{ name: "pi" address: "127.0.0.2" ros_from_system: true python: "{python}" }}
  host {{ name: "box" address: "127.0.0.3" }}
  node {{ name: "leader" type: ENCODER_PUBLISHER host: "pi" topic_name: "/leader/joint_states"
         serial_port: "/dev/ttyLEADER" }}
  node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER host: "box" topic_name: "/leader/joint_states" }}
}}
"""
# How this machine reaches PyPI and where uv keeps its cache: all a robot's shell would add to PATH and HOME.
PYPI_ACCESS_VARIABLES = ("SSL_CERT_FILE", "SSL_CERT_DIR", "HTTPS_PROXY", "https_proxy", "NO_PROXY", "no_proxy")
PYPI_ACCESS_VARIABLES += ("UV_INDEX_URL", "UV_DEFAULT_INDEX", "UV_NATIVE_TLS", "UV_CACHE_DIR")
# Runs `sh install.sh VENV` in a private mount namespace whose /opt is an empty tmpfs, plus setup.sh when given.
IN_NAMESPACE = """
mount -t tmpfs -o mode=755 joshua-test /opt
if [ -n "$1" ]; then mkdir -p /opt/ros/jazzy && cp "$1" /opt/ros/jazzy/setup.sh; fi
shift
exec sh "$@"
"""


@pytest.fixture(scope="module")
def apt_arm_bundle(tmp_path_factory) -> Path:
    """The two-host robot built with its bundles, the pi's python a 3.12 found here."""
    directory = tmp_path_factory.mktemp("apt_arm")
    source = directory / "apt_arm.pbtxt"
    source.write_text(DESCRIPTION.format(python=SYSTEM_PYTHONS.get(APT_JAZZY_PYTHON, "/usr/bin/python3")))
    built = joshuac("build", source, "-o", directory / "out", "--bundle")
    assert built.returncode == 0, built.stderr
    return directory / "out" / "hosts"


def clean_environment(tmp_path: Path, **extra) -> dict:
    tools = tmp_path / "tools"
    tools.mkdir(exist_ok=True)
    if not (tools / "uv").exists():
        (tools / "uv").symlink_to(find_uv_bin())
    access = {name: os.environ[name] for name in PYPI_ACCESS_VARIABLES if name in os.environ}
    return {**access, "PATH": f"{tools}:/usr/bin:/bin", "HOME": os.environ["HOME"], **extra}


def install(host_dir: Path, venv: Path, tmp_path: Path, setup_script: Path | None, **extra):
    """install.sh of `host_dir` into `venv` with a private /opt holding `setup_script` as apt's ROS setup."""
    return subprocess.run(
        ["unshare", "--mount", "--propagation", "private", "sh", "-c", IN_NAMESPACE, "in-namespace"]
        + [str(setup_script or ""), str(host_dir / "install.sh"), str(venv)],
        cwd=tmp_path,
        env=clean_environment(tmp_path, **extra),
        capture_output=True,
        text=True,
        timeout=INSTALL_TIMEOUT_S,
    )


def stand_in_setup(tmp_path: Path) -> Path:
    script = tmp_path / "setup.sh"
    script.write_text(f'echo "{SOURCED}" >&2\nexport ROS_DISTRO=jazzy\n')
    return script


@pytest.mark.timeout(2 * INSTALL_TIMEOUT_S)
@pytest.mark.parametrize("version", sorted(SYSTEM_PYTHONS))
def test_the_bundle_installs_on_apts_python_and_its_tools_work(version, apt_arm_bundle, tmp_path):
    venv = tmp_path / "venv"
    installed = install(apt_arm_bundle / "pi", venv, tmp_path, stand_in_setup(tmp_path))
    assert installed.returncode == 0, installed.stdout + installed.stderr
    assert SOURCED in installed.stderr
    assert f"joshua_runtime installed in {venv}" in installed.stdout
    assert "include-system-site-packages = true" in (venv / "pyvenv.cfg").read_text()
    probe = subprocess.run(
        [str(venv / "bin" / "python"), "-c", _PROBE],
        cwd=tmp_path,
        env=clean_environment(tmp_path),
        capture_output=True,
        text=True,
        timeout=TOOL_TIMEOUT_S,
    )
    assert probe.returncode == 0, probe.stderr
    python, rclpy, runtime = probe.stdout.split()
    assert (python, rclpy) == (version, "None")  # no ROS wheel: ROS comes from apt
    assert runtime.startswith(str(venv))

    link = tmp_path / "ttyBUS"
    emulator = subprocess.Popen(
        [str(venv / "bin" / "joshua-emulate"), "sts3215", "--ids", "2,5", "--link", str(link)],
        env=clean_environment(tmp_path),
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert "sts3215: servos 2,5" in emulator.stdout.readline()
        scan = subprocess.run(
            [str(venv / "bin" / "joshua-servo"), "scan", str(link), "--json"],
            env=clean_environment(tmp_path),
            capture_output=True,
            text=True,
            timeout=TOOL_TIMEOUT_S,
        )
        assert scan.returncode == 0, scan.stderr
        assert [(servo["id"], servo["baud_rate"]) for servo in json.loads(scan.stdout)] == [
            (2, 1_000_000),
            (5, 1_000_000),
        ]
    finally:
        emulator.send_signal(signal.SIGINT)
        assert emulator.wait(TOOL_TIMEOUT_S) == 0


_PROBE = (
    "import sys, importlib.util, joshua_runtime\n"
    "print('%d.%d' % sys.version_info[:2], importlib.util.find_spec('rclpy'), joshua_runtime.__file__)\n"
)


@pytest.mark.parametrize("version", sorted(SYSTEM_PYTHONS))
def test_without_apts_ros_the_install_is_refused_in_one_line(version, apt_arm_bundle, tmp_path):
    venv = tmp_path / "venv"
    installed = install(apt_arm_bundle / "pi", venv, tmp_path, None)
    assert installed.returncode == 1
    assert installed.stderr == (
        f"install.sh: {ROS_SETUP} is missing: this host takes ROS 2 Jazzy from apt (ros_from_system); "
        "nothing installed\n"
    )
    assert not venv.exists()


@pytest.mark.parametrize("version", sorted(SYSTEM_PYTHONS))
def test_a_host_with_the_ros_wheels_refuses_another_python_than_theirs(version, apt_arm_bundle, tmp_path):
    venv = tmp_path / "venv"
    installed = install(apt_arm_bundle / "box", venv, tmp_path, None, PYTHON=str(SYSTEM_PYTHONS[version]))
    assert installed.returncode == 1
    assert installed.stderr == (
        f"install.sh: {SYSTEM_PYTHONS[version]} is Python {version} on x86_64, and the ROS 2 wheels on PyPI exist "
        "for Python 3.11 on x86_64 only (a host with ros_from_system takes ROS 2 from apt); nothing installed\n"
    )
    assert not venv.exists()
