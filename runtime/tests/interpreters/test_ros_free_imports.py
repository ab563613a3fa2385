"""The ROS-free parts of the runtime import with ROS absent, as on a computer whose ROS comes from apt and is not
sourced, or on a Python the ROS wheels do not exist for.

Every module of the packages below is imported in a fresh interpreter of the development environment in which
every top-level package of the ROS 2 wheels (rclpy, the message packages, ...) is made unimportable. Their
tests also run without ROS on each other Python (test_ros_free_tests_on_each_python.py); this check covers
the modules those tests do not import.
"""

import importlib.metadata
import json
import subprocess
import sys

from testsupport.joshuac_cli import ROOT

ROS_FREE_PACKAGES = (
    "joshua_runtime.drivers",
    "joshua_runtime.emulators",
    "joshua_runtime.servo_tools",
    "joshua_runtime.dashboard",
    "joshua_runtime.description",
    "joshua_runtime.odometry",
)
# The dashboard's reader of the robot's topics, which it imports once its settings are checked.
ROS_SIDE = ("joshua_runtime.dashboard.telemetry",)
HUB_PROGRAMS = ("joshua_runtime.drivers.pybricks_hub_program",)  # MicroPython for the LEGO hub, never imported here
ROS_DISTRIBUTION_PREFIX = "ros-"  # the ROS 2 wheels on PyPI: ros-rclpy, ros-sensor-msgs, ...
IMPORT_TIMEOUT_S = 120

_IMPORT_EACH = """
import importlib, json, pkgutil, sys
blocked, packages, ros_side, skipped = json.loads(sys.argv[1])
for name in blocked:
    sys.modules[name] = None  # `import name` raises ImportError
modules = []
for name in packages:
    package = importlib.import_module(name)
    modules.append(name)
    for info in pkgutil.walk_packages(getattr(package, "__path__", []), name + "."):
        if info.name not in ros_side + skipped and not info.name.endswith(".__main__"):  # -m runs, not imports
            importlib.import_module(info.name)
            modules.append(info.name)
for name in ros_side:
    try:
        importlib.import_module(name)
    except ImportError:
        continue
    raise SystemExit(f"{name} imported although ROS is blocked")
print(json.dumps(modules))
"""


def ros_top_level_packages() -> list[str]:
    """The importable top-level names that the installed ROS 2 wheels ship."""
    names = set()
    for distribution in importlib.metadata.distributions():
        if not distribution.metadata["Name"].lower().startswith(ROS_DISTRIBUTION_PREFIX):
            continue
        for file in distribution.files or ():
            top = file.parts[0]
            if len(file.parts) > 1 and top.isidentifier() and not top.endswith((".libs", ".data")):
                names.add(top)
    return sorted(names)


def test_the_ros_wheels_provide_rclpy_and_the_message_packages():
    names = ros_top_level_packages()
    assert {"rclpy", "sensor_msgs", "std_msgs", "builtin_interfaces", "rcl_interfaces"} <= set(names), names


def test_ros_free_modules_import_without_ros():
    argument = json.dumps([ros_top_level_packages(), ROS_FREE_PACKAGES, ROS_SIDE, HUB_PROGRAMS])
    result = subprocess.run(
        [sys.executable, "-c", _IMPORT_EACH, argument],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=IMPORT_TIMEOUT_S,
    )
    assert result.returncode == 0, result.stderr[-4000:]
    imported = json.loads(result.stdout)
    assert {"joshua_runtime.drivers.sts3215", "joshua_runtime.dashboard.cli", "joshua_runtime.odometry"} <= set(
        imported
    )


_DASHBOARD_WITHOUT_ROS = """
import json, sys
for name in json.loads(sys.argv[1]):
    sys.modules[name] = None
from joshua_runtime.dashboard.cli import main
raise SystemExit(main(sys.argv[2:]))
"""


def test_the_dashboard_tells_a_settings_mistake_in_one_line_without_ros(tmp_path):
    missing = tmp_path / "out" / "manifest.json"
    result = subprocess.run(
        [sys.executable, "-c", _DASHBOARD_WITHOUT_ROS, json.dumps(ros_top_level_packages())]
        + ["--manifest", str(missing), "--port", "0"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=IMPORT_TIMEOUT_S,
    )
    assert result.returncode != 0
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith("dashboard: error: "), result.stderr
    assert str(missing) in result.stderr
