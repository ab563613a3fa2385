"""C++ nodes on bad input: one line on stderr with the Python node's message and exit code, never a hang.

Also how the binaries read `--ros-args`: string parameters stay strings whatever their quoting, and a
signal during start-up still ends the node cleanly.
"""

import math
import signal
import time

import pytest
from cpp_support import NODE_START_TIMEOUT_S, STOP_BOUND_S, cpp_commands, error_line
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState, LaserScan

from joshua_core.device_link import DEVICE_SILENCE_S
from testsupport.compiled_settings import compiled_settings

SO100_BUS = 'device_ids: [1, 2, 3, 4, 5, 6]'
PAIR = """
robot_config {{
  name: "errors"
  mode: MODE_TELEOPERATION
  node {{ name: "py_node" type: {type} preferred_backend: PYTHON topic_name: "/py" serial_port: "{port}-py" {fields} }}
  node {{ name: "cpp_node" type: {type} preferred_backend: CPP topic_name: "/cpp" serial_port: "{port}-cpp" {fields} }}
}}
"""
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
SENSOR_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)


def with_parameter(argv: list[str], override: str) -> list[str]:
    """`argv` with `-p NAME:=VALUE` replacing the parameter's value given there (or added)."""
    name = override.split(":=")[0]
    kept = [arg for arg in argv if not arg.startswith(f"{name}:=")]
    if len(kept) < len(argv):
        index = argv.index(next(arg for arg in argv if arg.startswith(f"{name}:=")))
        return argv[:index] + [override] + argv[index + 1:]
    return argv + ["-p", override]


def pair(node_type: str, fields: str = SO100_BUS, port: str = "/dev/joshua-absent") -> str:
    """A description of a Python and a C++ node of one type, on serial ports `<port>-py` and `<port>-cpp`."""
    return PAIR.format(type=node_type, fields=fields, port=port)


def run_pair(start_node, start_cpp, text: str, overrides=()) -> list[tuple[int, str]]:
    """(exit code, error message with `-py`/`-cpp` cut out) of the two nodes of `text`, each run to its end."""
    python = start_node(compiled_settings(text, overrides)["py_node"])
    cpp = start_cpp(cpp_commands(text, overrides)["cpp_node"])
    results = []
    for node, suffix in ((python, "-py"), (cpp, "-cpp")):
        code, stderr = node.wait(NODE_START_TIMEOUT_S)
        assert len(stderr.strip().splitlines()) == 1, stderr
        results.append((code, error_line(stderr).replace(suffix, "")))
    return results


@pytest.mark.parametrize("node_type, fields", [
    ("ENCODER_PUBLISHER", SO100_BUS), ("ACTUATOR_SUBSCRIBER", SO100_BUS), ("LIDAR_PUBLISHER", ""),
])
def test_a_missing_device_ends_both_nodes_alike(start_node, start_cpp, node_type, fields):
    (python_code, python_text), (cpp_code, cpp_text) = run_pair(start_node, start_cpp, pair(node_type, fields))
    assert cpp_code == python_code == 3
    if node_type == "LIDAR_PUBLISHER":  # the Python node's reason is pyserial's wording of ENOENT
        assert cpp_text.split(": ")[0] == python_text.split(": ")[0] == "cannot open LDS-01 lidar at /dev/joshua-absent"
        assert "No such file or directory" in python_text and cpp_text.endswith("No such file or directory")
    else:
        assert cpp_text == python_text == "serial port /dev/joshua-absent not found"


def test_a_lidar_that_stops_streaming_ends_both_nodes_alike(lidars, start_node, start_cpp, ros_client):
    python_lidar, cpp_lidar = lidars("ttySTALL-py"), lidars("ttySTALL-cpp")
    text, overrides = pair("LIDAR_PUBLISHER", ""), [f"py_node.serial_port={python_lidar.link}",
                                                  f"cpp_node.serial_port={cpp_lidar.link}"]
    python = start_node(compiled_settings(text, overrides)["py_node"])
    cpp = start_cpp(cpp_commands(text, overrides)["cpp_node"])
    ros_client.listen("/py", LaserScan, SENSOR_QOS)
    ros_client.listen("/cpp", LaserScan, SENSOR_QOS)
    assert ros_client.spin_until(lambda: ros_client.last("/py") and ros_client.last("/cpp"), NODE_START_TIMEOUT_S), (
        python.failure(), cpp.failure())
    python_lidar.stream.spinning = cpp_lidar.stream.spinning = False  # motors stall: ports stay, data stops
    for node, suffix in ((python, "-py"), (cpp, "-cpp")):
        code, stderr = node.wait(NODE_START_TIMEOUT_S)
        assert code == 3, stderr
        assert error_line(stderr).replace(suffix, "") == (
            f"LDS-01 lidar at {python_lidar.link.parent}/ttySTALL stopped streaming: "
            f"no usable scan for {DEVICE_SILENCE_S:g} s")


def test_a_calibration_file_without_the_joints_is_unusable_settings(tmp_path, buses, start_node, start_cpp):
    calibration = tmp_path / "other_arm.json"
    calibration.write_text('{"elbow": {"id": 1, "drive_mode": 0, "homing_offset": 0, "range_min": 0, '
                           '"range_max": 4095}}')
    buses("ttyBUS-py"), buses("ttyBUS-cpp")
    text = pair("ENCODER_PUBLISHER", f'{SO100_BUS} calibration_file: "{calibration}"', str(tmp_path / "ttyBUS"))
    python, cpp = run_pair(start_node, start_cpp, text)
    assert cpp == python
    assert cpp[0] == 2 and "has no entry for shoulder_pan" in cpp[1]


@pytest.mark.parametrize("override, message", [
    ("rate_hz:=fast", "parameter rate_hz must be a number"),
    ("rate_hz:=0", "rate_hz must be positive, got 0"),
    ("device_ids:=[one, two]", "parameter device_ids must be a list of integers"),
    ("qos_reliability:=SOMETIMES", "parameter qos_reliability has unknown value SOMETIMES"),
    ("topic_name:=[", "invalid --ros-args: Couldn't parse parameter override rule: '-p topic_name:=['."),
])
def test_unusable_parameters_exit_2_with_one_line(start_cpp, override, message):
    argv = with_parameter(cpp_commands(pair("ENCODER_PUBLISHER"))["cpp_node"], override)
    code, stderr = start_cpp(argv).wait()
    assert (code, stderr.strip().splitlines()) == (2, [f"cpp_node: error: {message}" if "--ros-args" not in message
                                                       else stderr.strip()]), stderr
    assert message in stderr


@pytest.mark.parametrize("quoted", ["'0042'", "'true'", "base_link"])
def test_string_parameters_stay_strings(buses, start_cpp, ros_client, quoted):
    bus = buses("ttyBUS")
    argv = cpp_commands(pair("ENCODER_PUBLISHER"), [f"cpp_node.serial_port={bus.link}"])["cpp_node"]
    node = start_cpp(with_parameter(argv, f"frame_id:={quoted}"))
    ros_client.listen("/cpp", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp") is not None, NODE_START_TIMEOUT_S), node.failure()
    assert ros_client.last("/cpp").header.frame_id == quoted.strip("'")


def test_a_signal_during_start_up_ends_the_node_with_0(buses, start_cpp):
    silent = buses("ttySILENT", ids=[7])  # answers nothing the node asks for: it retries every servo
    node = start_cpp(cpp_commands(pair("ENCODER_PUBLISHER"), [f"cpp_node.serial_port={silent.link}"])["cpp_node"])
    time.sleep(0.2)
    code, seconds, stderr = node.stop(signal.SIGTERM)
    assert (code, stderr) == (0, "")
    assert seconds < STOP_BOUND_S


def test_the_encoder_rides_out_a_replug_then_exits_3_when_the_bus_stays_gone(buses, start_cpp, ros_client):
    bus = buses("ttyREPLUG")
    node = start_cpp(cpp_commands(pair("ENCODER_PUBLISHER"), [f"cpp_node.serial_port={bus.link}"])["cpp_node"])
    ros_client.listen("/cpp", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp") is not None, NODE_START_TIMEOUT_S), node.failure()

    bus.stop()
    ros_client.spin_until(lambda: False, 0.5)
    bus.move_by_hand(1, 3000)
    bus.write_register(1, "Goal_Position", 3000)
    bus.write_register(1, "Torque_Enable", 1)  # a power-cycled leader must be released again
    bus.start()
    expected = (3000 - 4095 / 2) * 2 * math.pi / 4095
    assert ros_client.spin_until(lambda: abs(ros_client.last("/cpp").position[0] - expected) < 1e-9,
                                 NODE_START_TIMEOUT_S), (ros_client.last("/cpp"), node.failure())
    assert node.process.poll() is None
    assert bus.wait_until(lambda: bus.read_register(1, "Torque_Enable") == 0, NODE_START_TIMEOUT_S)

    bus.stop()
    code, stderr = node.wait()
    assert code == 3
    assert stderr.strip().splitlines()[-1] == (
        f"cpp_node: error: {bus.link}: bus failing for 3 s: serial port {bus.link} not found")
    assert "[INFO]" in stderr and f"{bus.link}: reconnected" in stderr


def test_the_encoder_retries_through_lost_and_corrupt_replies(buses, start_cpp, ros_client):
    noisy = buses("ttyNOISY", drop_rate=0.1, corrupt_rate=0.05, seed=3)
    for servo_id, ticks in zip(range(1, 7), (1000, 1500, 2000, 2500, 3000, 3500)):
        noisy.move_by_hand(servo_id, ticks)
    node = start_cpp(cpp_commands(pair("ENCODER_PUBLISHER"), [f"cpp_node.serial_port={noisy.link}"])["cpp_node"])
    ros_client.listen("/cpp", JointState, RELIABLE, keep=20)
    assert ros_client.spin_until(lambda: ros_client.count("/cpp") >= 20, NODE_START_TIMEOUT_S), node.failure()
    expected = [(ticks - 4095 / 2) * 2 * math.pi / 4095 for ticks in (1000, 1500, 2000, 2500, 3000, 3500)]
    for message in ros_client.messages("/cpp"):
        assert list(message.position) == pytest.approx(expected, abs=1e-12)
    assert noisy.stats["dropped"] > 0 and noisy.stats["corrupted"] > 0
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr


def test_a_port_held_by_another_node_is_busy_for_both_backends(buses, start_node, start_cpp, ros_client):
    bus = buses("ttyHELD")
    text = pair("ENCODER_PUBLISHER")
    overrides = [f"py_node.serial_port={bus.link}", f"cpp_node.serial_port={bus.link}-other"]
    holder = start_cpp(cpp_commands(text, [f"cpp_node.serial_port={bus.link}"])["cpp_node"])
    ros_client.listen("/cpp", JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/cpp") is not None, NODE_START_TIMEOUT_S), holder.failure()
    second_cpp = start_cpp(with_parameter(cpp_commands(text, overrides)["cpp_node"], f"serial_port:={bus.link}"))
    python = start_node(compiled_settings(text, overrides)["py_node"])
    results = [node.wait(NODE_START_TIMEOUT_S) for node in (python, second_cpp)]
    assert [(code, error_line(stderr)) for code, stderr in results] == [
        (3, f"serial port {bus.link} is busy: another program has it open")] * 2
    assert holder.process.poll() is None


def test_two_servos_sharing_an_id_stop_both_backends_alike(tmp_path, buses, start_node, start_cpp):
    for suffix in ("-py", "-cpp"):
        buses(f"ttyTWINS{suffix}", ids=[1, 1, 2, 3, 4, 5, 6])
    python, cpp = run_pair(start_node, start_cpp, pair("ENCODER_PUBLISHER", port=str(tmp_path / "ttyTWINS")))
    assert cpp == python == (3, f"{tmp_path / 'ttyTWINS'}: no answer from servo id 1")
