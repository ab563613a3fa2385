"""`make -C cpp ROS=PREFIX`: the C++ nodes built against ROS 2 as apt lays it out (`ROS=/opt/ros/jazzy`).

This machine has no apt ROS (Debian, while ROS 2 Jazzy's packages are Ubuntu 24.04's), so the test lays out a
prefix as apt does from the ROS 2 wheels of the development environment: include/<package>/<package>/...,
lib/ holding every library (the wheels' vendored ones too, as the system's are on Ubuntu) and share/ (the
ament index). apt's Python message libraries (lib*__rosidl_generator_py.so) depend on libpython, the
wheels' do not: their copies get that dependency with patchelf, so the prefix links as apt's does.

The flags name the prefix alone; a build into another directory links against it (the binaries' only rpath)
without any Python flags, and the encoder node so built publishes the emulated arm's joint states over DDS,
started with no library path in its environment.
"""

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest
from cpp_support import IDS, MESSAGE_TIMEOUT_S, READER_QOS, ROOT
from sensor_msgs.msg import JointState

from joshua_codegen.compile import cpp_commands

VENV = Path(sys.prefix)
SITE = Path(sysconfig.get_paths()["purelib"])
BUILD_TIMEOUT_S = 900  # every C++ source compiled once more, on a busy 2-core machine
PYTHON_MESSAGE_LIBRARIES = "*__rosidl_generator_py.so"
ENCODER = """
robot_config {{
  name: "prefix"
  mode: MODE_TELEOPERATION
  node {{ name: "leader" type: ENCODER_PUBLISHER preferred_backend: CPP serial_port: "{port}"
         device_ids: [1, 2, 3, 4, 5, 6] topic_name: "/leader/joint_states" rate_hz: 50 }}
}}
"""


def make(*arguments: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["make", "--no-print-directory", "-s", "-C", str(ROOT / "cpp"), *arguments],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def lay_out_like_apt(prefix: Path) -> Path:
    """A prefix laid out as apt's /opt/ros/jazzy, made of the development environment's ROS 2 wheels."""
    (prefix / "include").mkdir(parents=True)
    (prefix / "lib").mkdir()
    for package in sorted((VENV / "include").iterdir()):
        if package.name != "site":  # the virtual environment's own, not a ROS package
            (prefix / "include" / package.name).symlink_to(package)
    libraries = sorted((VENV / "lib").glob("*.so*")) + sorted(SITE.glob("ros_*.libs/*"))
    libpython = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var("INSTSONAME")
    for library in [*libraries, libpython]:
        target = prefix / "lib" / library.name
        if target.exists():  # the same vendored library in several wheels
            continue
        if library.match(PYTHON_MESSAGE_LIBRARIES):
            shutil.copyfile(library, target)
            subprocess.run([str(VENV / "bin" / "patchelf"), "--add-needed", libpython.name, str(target)], check=True)
        else:
            target.symlink_to(library)
    (prefix / "share").symlink_to(VENV / "share")
    return prefix


@pytest.fixture(scope="module")
def apt_prefix(tmp_path_factory) -> Path:
    return lay_out_like_apt(tmp_path_factory.mktemp("opt-ros") / "jazzy")


@pytest.fixture(scope="module")
def built(apt_prefix, tmp_path_factory) -> Path:
    """bin/ of the C++ nodes built against apt_prefix, in a directory of their own."""
    build = tmp_path_factory.mktemp("build")
    result = make(f"ROS={apt_prefix}", f"BUILD={build}", timeout=BUILD_TIMEOUT_S)
    assert result.returncode == 0, result.stdout + result.stderr
    return build / "bin"


def flags(*arguments: str) -> dict[str, list[str]]:
    result = make(*arguments, "flags")
    assert result.returncode == 0, result.stderr
    return {name: value.split() for name, value in (line.split("=", 1) for line in result.stdout.splitlines())}


def test_flags_name_the_prefixs_include_and_lib_directories_only(apt_prefix):
    apt = flags(f"ROS={apt_prefix}")
    include_dirs = [apt["CXXFLAGS"][i + 1] for i, word in enumerate(apt["CXXFLAGS"]) if word == "-isystem"]
    assert f"{apt_prefix}/include/rcl" in include_dirs and f"{apt_prefix}/include/sensor_msgs" in include_dirs
    assert f"{apt_prefix}/include" in include_dirs  # packages that install their headers there directly
    assert all(directory.startswith(f"{apt_prefix}/include") for directory in include_dirs), include_dirs
    assert f"-L{apt_prefix}/lib" in apt["LDFLAGS"]
    assert [word for word in apt["LDFLAGS"] if "-rpath," in word] == [f"-Wl,-rpath,{apt_prefix}/lib"]
    assert not [word for word in apt["LDLIBS"] if word.startswith("-lpython")]
    assert ".venv" not in " ".join(sum(apt.values(), []))
    wheels = flags()  # without ROS: the wheels of .venv, with libpython
    assert f"-isystem {VENV}/include/rcl" in " ".join(wheels["CXXFLAGS"])
    assert any(word.startswith("-lpython3") for word in wheels["LDLIBS"])


def test_a_prefix_without_ros_is_refused_in_one_line(tmp_path):
    result = make(f"ROS={tmp_path}", f"BUILD={tmp_path / 'build'}")
    assert result.returncode != 0
    assert (
        f"cpp: {tmp_path}/lib/librcl.so missing: ROS={tmp_path} is not a ROS 2 installation "
        "(apt install ros-jazzy-ros-core puts one at /opt/ros/jazzy)"
    ) in result.stderr
    assert not (tmp_path / "build" / "bin").exists()


@pytest.mark.timeout(BUILD_TIMEOUT_S + 120)
def test_a_node_built_against_the_prefix_links_to_it_alone_and_publishes(
    apt_prefix, built, buses, start_cpp, ros_client, ros_env
):
    binary = built / "encoder_publisher"
    dynamic = subprocess.run(["readelf", "-d", str(binary)], capture_output=True, text=True, check=True).stdout
    rpaths = [line.split("[", 1)[1].rstrip("]") for line in dynamic.splitlines() if "(RPATH)" in line]
    assert rpaths == [f"{apt_prefix}/lib"]
    assert "libpython" not in dynamic  # apt's message libraries bring it themselves
    for variable in ("LD_LIBRARY_PATH", "AMENT_PREFIX_PATH"):
        ros_env.pop(variable, None)
    resolved = subprocess.run(["ldd", str(binary)], capture_output=True, text=True, env=ros_env, check=True).stdout
    assert "not found" not in resolved, resolved
    assert f"librcl.so => {apt_prefix}/lib/librcl.so" in resolved

    bus = buses("ttyBUS")
    (argv,) = cpp_commands(ENCODER.format(port=bus.link), str(built)).values()
    node = start_cpp(argv)
    ros_client.listen("/leader/joint_states", JointState, READER_QOS)
    for servo_id in IDS:
        bus.move_by_hand(servo_id, 1000 + 300 * servo_id)

    def moved() -> bool:
        message = ros_client.last("/leader/joint_states")
        return message is not None and len(set(message.position)) == len(IDS)

    assert ros_client.spin_until(moved, MESSAGE_TIMEOUT_S), node.process.poll()
    assert os.path.realpath(argv[0]) == str(binary)
