"""Fixtures shared by every test: an isolated ROS 2 environment per test, nodes started in it, a client,
emulated devices on pseudo-terminals.

Shared helpers live in the package testsupport/ beside this file, importable from every test.
"""

import os
import sys

import pytest

from testsupport.node_process import NodeProcess
from testsupport.ros_domains import claimed_domain

pytest_plugins = [
    "testsupport.tiers",  # marks every test with its tiers (unit, process, ros, ...)
    "testsupport.xdist_groups",  # keeps the tests of an xdist_group on one worker
    "testsupport.cpu_durations",  # --cpu-durations=N: the tests that cost the most CPU
    "testsupport.shm_leftovers",  # Fast DDS files the tests' killed processes left in /dev/shm go at the end
]

# pytest keeps the test modules it rewrites (for its assertions) compiled in __pycache__, as set-up keeps the
# project's; where PYTHONDONTWRITEBYTECODE is set it would rewrite and compile all of them again in every worker
# of every run (7.5 s of CPU each). Processes the tests start keep the environment's setting.
sys.dont_write_bytecode = False

# MuJoCo reads MUJOCO_GL once, at its first import in a process; tests that render in this process (the
# training demonstrations) need EGL, as there is no display. Node processes choose their own.
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
# One thread per process for the math libraries (OpenMP: torch, OpenBLAS), in this process and every one
# it starts: `make test` runs a worker per core, and OpenMP threads spinning for cores that other processes
# hold multiply torch's CPU time (ResNet-18 on a 64x48 image: 14 CPU-ms with one thread, 224 with two on a
# busy 2-core machine; `joshua-train evaluate` of the AI README's ACT: 7.5 CPU-s against 30).
os.environ.setdefault("OMP_NUM_THREADS", "1")


@pytest.fixture(autouse=True)
def private_state_dirs(tmp_path_factory, monkeypatch) -> None:
    """Supervisors a test starts keep their node logs ($XDG_STATE_HOME) and control socket
    ($XDG_RUNTIME_DIR) in directories of that test, never in the user's own."""
    base = tmp_path_factory.mktemp("xdg")
    for variable, name in (("XDG_STATE_HOME", "state"), ("XDG_RUNTIME_DIR", "run")):
        (base / name).mkdir(mode=0o700)
        monkeypatch.setenv(variable, str(base / name))


@pytest.fixture
def ros_env(request):
    """Environment for ROS processes of this test: its own domain id, discovery on localhost only.

    The id (testsupport/ros_domains.py) and the two after it are this test's alone while it runs, also
    against parallel workers and other checkouts testing at once on this machine.
    """
    with claimed_domain(f"{request.config.rootpath}::{request.node.nodeid}") as domain:
        env = dict(os.environ)
        env["ROS_DOMAIN_ID"] = str(domain)
        env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
        env["PYTHONUNBUFFERED"] = "1"
        yield env


@pytest.fixture
def ros_domain(ros_env, monkeypatch) -> int:
    """Put this process in the test's ROS domain too (for an in-process rclpy client)."""
    for key in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE"):
        monkeypatch.setenv(key, ros_env[key])
    return int(ros_env["ROS_DOMAIN_ID"])


@pytest.fixture
def start_node(ros_env):
    """Factory: start_node(settings, **extra_env) -> a NodeProcess in the test's ROS domain; killed at teardown."""
    started = []

    def start(settings: dict, **extra_env) -> NodeProcess:
        node = NodeProcess(settings, dict(ros_env, **extra_env))
        started.append(node)
        return node

    yield start
    for node in started:
        node.kill()


@pytest.fixture
def ros_client(ros_domain):
    """An in-process rclpy client (testsupport.ros_client.RosClient) in the test's ROS domain; closed at teardown."""
    from testsupport.ros_client import RosClient

    with RosClient("test_client") as client:
        yield client


@pytest.fixture
def emulators(tmp_path):
    """Factory: emulators(name, **options) -> a started Sts3215Emulator (a servo bus; servos 1-6 unless
    `ids=` says otherwise) at tmp_path/name; stopped at teardown."""
    from joshua_runtime.emulators.sts3215 import Sts3215Emulator

    started = []

    def make(name: str = "ttyBUS", **options) -> Sts3215Emulator:
        emulator = Sts3215Emulator(tmp_path / name, **options).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()


@pytest.fixture
def buses(emulators):
    """The same factory as `emulators`, by the name the C++ node tests give it."""
    return emulators


@pytest.fixture
def lidars(tmp_path):
    """Factory: lidars(name, **options) -> a started Lds01Emulator at tmp_path/name; stopped at teardown."""
    from joshua_runtime.emulators.lds01 import Lds01Emulator

    started = []

    def make(name: str, **options) -> Lds01Emulator:
        emulator = Lds01Emulator(tmp_path / name, **options).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()
