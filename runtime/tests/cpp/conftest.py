"""Fixtures of the C++ node tests: the binaries built once per session, C++ node processes, emulators."""

import json
import subprocess

import pytest
from cpp_support import BIN_DIR, CALIBRATION, ROOT, CppNodeProcess

from joshua_runtime.emulators.lds01 import Lds01Emulator
from joshua_runtime.emulators.sts3215 import Sts3215Emulator

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
def buses(tmp_path):
    """Factory: buses(name, **options) -> a started Sts3215Emulator (servos 1-6) at tmp_path/name."""
    started = []

    def make(name: str, **options) -> Sts3215Emulator:
        emulator = Sts3215Emulator(tmp_path / name, **options).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()


@pytest.fixture
def lidars(tmp_path):
    """Factory: lidars(name) -> a started Lds01Emulator at tmp_path/name."""
    started = []

    def make(name: str) -> Lds01Emulator:
        emulator = Lds01Emulator(tmp_path / name).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()


@pytest.fixture
def calibration_file(tmp_path):
    """A calibration file of the SO-100 joints (cpp_support.CALIBRATION)."""
    path = tmp_path / "so100.json"
    path.write_text(json.dumps(CALIBRATION))
    return path
