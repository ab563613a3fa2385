"""Fixtures of the C++ node tests: the binaries built once per session, C++ node processes (emulators: root conftest)."""

import json
import subprocess

import pytest
from cpp_support import BIN_DIR, CALIBRATION, ROOT, CppNodeProcess

BINARIES = ("encoder_publisher", "actuator_subscriber", "lidar_publisher")


@pytest.fixture(scope="session")
def cpp_bin_dir():
    """build/bin with every C++ node binary; `make cpp` is a no-op when setup has built them."""
    result = subprocess.run(["make", "--no-print-directory", "-s", "-C", str(ROOT / "cpp")], capture_output=True,
                            text=True, check=False)
    assert result.returncode == 0, f"make cpp failed:\n{result.stdout}{result.stderr}"
    missing = [name for name in BINARIES if not (BIN_DIR / name).is_file()]
    assert not missing, f"make cpp built no {missing}"
    return BIN_DIR


@pytest.fixture
def start_cpp(ros_env, cpp_bin_dir):
    """Factory: start_cpp(argv) -> a CppNodeProcess in the test's ROS domain; killed at teardown."""
    started = []

    def start(argv: list[str]) -> CppNodeProcess:
        node = CppNodeProcess(argv, ros_env)
        started.append(node)
        return node

    yield start
    for node in started:
        node.kill()


@pytest.fixture
def calibration_file(tmp_path):
    """A calibration file of the SO-100 joints (cpp_support.CALIBRATION)."""
    path = tmp_path / "so100.json"
    path.write_text(json.dumps(CALIBRATION))
    return path
