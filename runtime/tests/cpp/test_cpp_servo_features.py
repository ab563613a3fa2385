"""The C++ servo nodes' /diagnostics, clamping report, command watchdog and presets, against their Python twins.

Each test compiles one description with a Python and a C++ node of the same type on their own emulated
bus, runs both over real DDS with the command line the generated supervisor gives the binary, puts the
same state into both emulators and compares what the nodes publish and leave on their buses.
"""

import math
import signal
import time

import pytest
from cpp_support import CALIBRATION, IDS, JOINTS, MESSAGE_TIMEOUT_S, NODE_START_TIMEOUT_S, READER_QOS, twins
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.calibration import MotorCalibration

OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR
KEPT_DIAGNOSTICS = 200
# The same trouble on both buses: near and over temperature, low and near-limit voltage, error bits.
TROUBLE = {
    2: [("set_sensor", "Present_Temperature", 63)],
    3: [("set_sensor", "Present_Voltage", 35)],
    4: [("set_sensor", "Present_Voltage", 44)],
    5: [("set_sensor", "Present_Temperature", 75), ("inject_error", proto.ERROR_OVERCURRENT | proto.ERROR_OVERLOAD)],
}
EXPECTED_LEVELS = {
    "shoulder_pan": OK,
    "shoulder_lift": WARN,
    "elbow_flex": ERROR,
    "wrist_flex": WARN,
    "wrist_roll": ERROR,
    "gripper": OK,
}


def statuses_of(ros_client, node: str, accept=lambda statuses: True) -> dict[str, DiagnosticStatus] | None:
    """The newest /diagnostics statuses of `node` by joint that `accept`, or None."""
    for message in reversed(ros_client.messages("/diagnostics")):
        statuses = {s.name.split(": ", 1)[1]: s for s in message.status if s.name.startswith(f"{node}: ")}
        if statuses and accept(statuses):
            return statuses
    return None


def comparable(status: DiagnosticStatus) -> tuple:
    """What a status says, without the node name and port that differ between the twins, and with the count of
    failed reads as whether it is a count: a read that timed out on a busy machine counts in one twin only."""
    return (
        status.level,
        status.message,
        status.hardware_id.rsplit(" id ", 1)[1],
        [(item.key, item.value.isdigit() if item.key == "read_failures" else item.value) for item in status.values],
    )


def stop(node) -> str:
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
    return stderr


def test_encoders_report_the_same_diagnostics(buses, start_node, start_cpp, ros_client):
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    settings, argv = twins(
        "leader",
        "ENCODER_PUBLISHER",
        "joint_states",
        "diagnostics_rate_hz: 10",
        [f"py_leader.serial_port={python_bus.link}", f"cpp_leader.serial_port={cpp_bus.link}"],
    )
    assert "diagnostics_rate_hz:=10.0" in argv
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/diagnostics", DiagnosticArray, READER_QOS, keep=KEPT_DIAGNOSTICS)
    for bus in (python_bus, cpp_bus):
        bus.move_by_hand(1, 1234)
        for servo_id, changes in TROUBLE.items():
            for method, *arguments in changes:
                getattr(bus, method)(servo_id, *arguments)

    def judged(statuses) -> bool:
        return {joint: status.level for joint, status in statuses.items()} == EXPECTED_LEVELS

    def both_judged() -> bool:
        return statuses_of(ros_client, "py_leader", judged) and statuses_of(ros_client, "cpp_leader", judged)

    assert ros_client.spin_until(both_judged, NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    python_statuses = statuses_of(ros_client, "py_leader", judged)
    cpp_statuses = statuses_of(ros_client, "cpp_leader", judged)
    assert list(cpp_statuses) == JOINTS
    assert {joint: comparable(s) for joint, s in cpp_statuses.items()} == {
        joint: comparable(s) for joint, s in python_statuses.items()
    }
    assert cpp_statuses["wrist_roll"].message == (
        "servo reports overheat; servo reports over-current; servo reports overload; temperature 75 C at or above 70 C"
    )
    assert cpp_statuses["shoulder_pan"].hardware_id == f"{cpp_bus.link} id 1"
    assert ("position_ticks", "1234") in [(i.key, i.value) for i in cpp_statuses["shoulder_pan"].values]
    publishers = {info.node_name: info for info in ros_client.publishers_info("/diagnostics", MESSAGE_TIMEOUT_S)}
    assert sorted(publishers) == ["cpp_leader", "py_leader"]
    assert {
        (info.topic_type, info.qos_profile.reliability, info.qos_profile.durability) for info in publishers.values()
    } == {("diagnostic_msgs/msg/DiagnosticArray", ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE)}
    stop(python), stop(cpp)


def start_follower_twins(buses, start_node, start_cpp, ros_client, fields: str, calibration_file):
    """Python and C++ actuators on their own buses, both following /command; started and subscribed."""
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    overrides = [
        f"py_follower.serial_port={python_bus.link}",
        f"cpp_follower.serial_port={cpp_bus.link}",
        f"py_follower.calibration_file={calibration_file}",
        f"cpp_follower.calibration_file={calibration_file}",
    ]
    settings, argv = twins("follower", "ACTUATOR_SUBSCRIBER", "command", fields, overrides)
    settings["topic"]["name"] = "/command"
    argv = [("topic_name:='/command'" if arg.startswith("topic_name:=") else arg) for arg in argv]
    python, cpp = start_node(settings), start_cpp(argv)
    for topic in ("/command", "/command/preset"):

        def both_follow(topic=topic) -> bool:
            followers = ros_client.node.get_subscriptions_info_by_topic(topic)
            return sorted(info.node_name for info in followers) == ["cpp_follower", "py_follower"]

        assert ros_client.spin_until(both_follow, NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    presets = ros_client.subscriptions_info("/command/preset", MESSAGE_TIMEOUT_S)
    assert {(info.topic_type, info.qos_profile.reliability, info.qos_profile.durability) for info in presets} == {
        ("std_msgs/msg/String", ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE)
    }
    return (python_bus, cpp_bus), (python, cpp)


def goals(bus) -> list[int]:
    return [bus.read_register(i, "Goal_Position") for i in IDS]


def torque(bus) -> list[int]:
    return [bus.read_register(i, "Torque_Enable") for i in IDS]


def test_actuators_report_clamped_goals_alike(buses, calibration_file, start_node, start_cpp, ros_client):
    (python_bus, cpp_bus), (python, cpp) = start_follower_twins(
        buses, start_node, start_cpp, ros_client, "diagnostics_rate_hz: 20 keep_torque_on_exit: true", calibration_file
    )
    ros_client.listen("/diagnostics", DiagnosticArray, READER_QOS, keep=KEPT_DIAGNOSTICS)
    commands = ros_client.publisher("/command", JointState, READER_QOS)
    commands.publish(JointState(name=["shoulder_pan", "gripper"], position=[9.0, 0.1]))
    applied = MotorCalibration(**CALIBRATION["shoulder_pan"]).to_radians(CALIBRATION["shoulder_pan"]["range_max"])
    note = f"shoulder_pan goal 9.000 rad clamped to {applied:.3f} rad"

    def noted(statuses) -> bool:
        return note in statuses["shoulder_pan"].message

    assert ros_client.spin_until(
        lambda: statuses_of(ros_client, "py_follower", noted) and statuses_of(ros_client, "cpp_follower", noted),
        MESSAGE_TIMEOUT_S,
    ), (python.failure(), cpp.failure())
    for node in ("py_follower", "cpp_follower"):
        statuses = statuses_of(ros_client, node, noted)
        assert statuses["shoulder_pan"].level >= WARN
        assert all(("goals_clamped", "1") in [(i.key, i.value) for i in s.values] for s in statuses.values())
    assert goals(cpp_bus) == goals(python_bus)
    assert cpp_bus.read_register(1, "Goal_Position") == CALIBRATION["shoulder_pan"]["range_max"]

    def note_gone_counter_kept() -> bool:  # the note is for one publication; the counter stays
        newest = statuses_of(ros_client, "cpp_follower")
        return note not in newest["shoulder_pan"].message and ("goals_clamped", "1") in [
            (i.key, i.value) for i in newest["shoulder_pan"].values
        ]

    assert ros_client.spin_until(note_gone_counter_kept, MESSAGE_TIMEOUT_S)
    for node in (python, cpp):
        assert f"outside the calibrated range: {note}" in stop(node)


@pytest.mark.parametrize("action", ["RELEASE_TORQUE", "HOLD_POSITION"])
def test_the_watchdog_stops_the_arm_when_goals_stop(action, buses, calibration_file, start_node, start_cpp, ros_client):
    timeout_s = 0.4
    fields = f"command_timeout_s: {timeout_s} on_command_timeout: {action} diagnostics_rate_hz: 10"
    buses_, nodes = start_follower_twins(buses, start_node, start_cpp, ros_client, fields, calibration_file)
    ros_client.listen("/diagnostics", DiagnosticArray, READER_QOS, keep=KEPT_DIAGNOSTICS)
    for bus in buses_:  # slow enough that the arm is still on its way when the watchdog fires
        for servo_id in IDS:
            bus.write_register(servo_id, "Goal_Velocity", 200)
    start = [buses_[1].position(i) for i in IDS]
    commands = ros_client.publisher("/command", JointState, READER_QOS)
    far = JointState(name=JOINTS, position=[1.0] * len(JOINTS))
    commands.publish(far)
    last_goal = time.monotonic()
    commanded = [MotorCalibration(**CALIBRATION[name]).to_ticks(1.0) for name in JOINTS]
    for bus in buses_:
        assert bus.wait_until(lambda bus=bus: goals(bus) == commanded, MESSAGE_TIMEOUT_S), nodes[1].failure()

    def stopped(bus) -> bool:
        if action == "RELEASE_TORQUE":
            return torque(bus) == [0] * 6
        return goals(bus) != commanded

    for bus in buses_:
        assert bus.wait_until(lambda bus=bus: stopped(bus), MESSAGE_TIMEOUT_S), nodes[1].failure()
    assert time.monotonic() - last_goal >= timeout_s
    cpp_bus = buses_[1]
    if action == "HOLD_POSITION":
        assert torque(cpp_bus) == [1] * 6
        held = goals(cpp_bus)
        assert all(min(a, b) < ticks < max(a, b) for ticks, a, b in zip(held, start, commanded)), (start, held)
        assert cpp_bus.wait_until(lambda: [cpp_bus.position(i) for i in IDS] == held, MESSAGE_TIMEOUT_S)
    condition = f"no goal for {timeout_s:g} s: " + (
        "torque released" if action == "RELEASE_TORQUE" else "holding position"
    )

    def reported(statuses) -> bool:
        return all(condition in status.message for status in statuses.values())

    assert ros_client.spin_until(
        lambda: statuses_of(ros_client, "py_follower", reported) and statuses_of(ros_client, "cpp_follower", reported),
        MESSAGE_TIMEOUT_S,
    )
    # The next goal resumes: torque back on, the goal taken, the condition gone.
    commands.publish(JointState(name=JOINTS, position=[0.2] * len(JOINTS)))
    resumed = [MotorCalibration(**CALIBRATION[name]).to_ticks(0.2) for name in JOINTS]
    for bus in buses_:
        assert bus.wait_until(lambda bus=bus: torque(bus) == [1] * 6 and goals(bus) == resumed, MESSAGE_TIMEOUT_S)
    stopped_by = "torque off until the next goal" if action == "RELEASE_TORQUE" else "holding the present position"
    for node in nodes:
        stderr = stop(node)
        assert f"no goal for {timeout_s:g} s: {stopped_by}" in stderr
        assert ("goal received: torque on again" in stderr) == (action == "RELEASE_TORQUE")


def test_presets_switch_torque_and_move_to_named_poses(buses, calibration_file, start_node, start_cpp, ros_client):
    fields = (
        'preset { name: "wave" joint { name: "elbow_flex" position: 0.5 } joint { name: "gripper" '
        "position: 1.0 } } keep_torque_on_exit: true"
    )
    buses_, nodes = start_follower_twins(buses, start_node, start_cpp, ros_client, fields, calibration_file)
    presets = ros_client.publisher("/command/preset", String, READER_QOS)
    motors = {name: MotorCalibration(**CALIBRATION[name]) for name in JOINTS}

    def send(name: str, done) -> None:
        assert ros_client.spin_until(
            lambda: all(done(bus) for bus in buses_),
            MESSAGE_TIMEOUT_S,
            every=lambda: presets.publish(String(data=name)),
        ), (name, nodes[1].failure())

    send("torque_off", lambda bus: torque(bus) == [0] * 6)
    send("torque_on", lambda bus: torque(bus) == [1] * 6)
    rest = {
        "shoulder_pan": 0.0,
        "shoulder_lift": -1.65,
        "elbow_flex": 1.55,
        "wrist_flex": 0.7,
        "wrist_roll": 0.0,
        "gripper": 0.0,
    }
    rest_ticks = [motors[name].to_ticks(rest[name]) for name in JOINTS]
    send(" rest ", lambda bus: goals(bus) == rest_ticks)
    wave_ticks = [
        motors[name].to_ticks({"elbow_flex": 0.5, "gripper": 1.0}[name]) if name in ("elbow_flex", "gripper") else ticks
        for name, ticks in zip(JOINTS, rest_ticks)
    ]
    send("wave", lambda bus: goals(bus) == wave_ticks)
    presets.publish(String(data="dance"))
    ros_client.spin_until(lambda: False, 0.5)
    assert goals(buses_[1]) == wave_ticks and not math.isnan(wave_ticks[0])
    for node in nodes:
        assert "unknown preset 'dance': known are torque_on, torque_off, home, rest, grip_open, wave" in stop(node)


def test_encoders_report_a_lost_bus_alike(buses, start_node, start_cpp, ros_client):
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    settings, argv = twins(
        "leader",
        "ENCODER_PUBLISHER",
        "joint_states",
        "diagnostics_rate_hz: 10",
        [f"py_leader.serial_port={python_bus.link}", f"cpp_leader.serial_port={cpp_bus.link}"],
    )
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/diagnostics", DiagnosticArray, READER_QOS, keep=KEPT_DIAGNOSTICS)

    def all_at(level):
        return lambda statuses: all(status.level == level for status in statuses.values())

    def both(accept) -> bool:
        return bool(statuses_of(ros_client, "py_leader", accept) and statuses_of(ros_client, "cpp_leader", accept))

    assert ros_client.spin_until(lambda: both(all_at(OK)), NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    python_bus.stop(), cpp_bus.stop()
    assert ros_client.spin_until(lambda: both(all_at(ERROR)), MESSAGE_TIMEOUT_S)
    for node, bus in (("py_leader", python_bus), ("cpp_leader", cpp_bus)):
        statuses = statuses_of(ros_client, node, all_at(ERROR))
        for index, (joint, status) in enumerate(statuses.items()):
            servo_id = index + 1
            # The port vanished ("disconnected: <why>"), then is not found on a retry.
            reason = status.message.removeprefix(f"servo id {servo_id} unreadable: serial port {bus.link} ")
            assert reason.startswith("disconnected: ") or reason == "not found", (node, status.message)
            values = dict((item.key, item.value) for item in status.values)
            assert list(values) == ["servo_id", "read_failures"] and int(values["read_failures"]) >= 1, (node, joint)
    # Past the grace period both end with the device's exit code.
    assert python.wait()[0] == cpp.wait()[0] == 3


def test_idle_actuators_report_a_lost_bus_alike_and_exit_3(buses, start_node, start_cpp, ros_client):
    """No state_topic and no goals: the diagnostics read (1 Hz by default) is what finds the bus gone."""
    python_bus, cpp_bus = buses("ttyPY"), buses("ttyCPP")
    settings, argv = twins(
        "follower",
        "ACTUATOR_SUBSCRIBER",
        "command",
        "",
        [f"py_follower.serial_port={python_bus.link}", f"cpp_follower.serial_port={cpp_bus.link}"],
    )
    python, cpp = start_node(settings), start_cpp(argv)
    ros_client.listen("/diagnostics", DiagnosticArray, READER_QOS, keep=KEPT_DIAGNOSTICS)

    def both_at(level) -> bool:
        def accept(statuses):
            return all(status.level == level for status in statuses.values())

        return bool(statuses_of(ros_client, "py_follower", accept) and statuses_of(ros_client, "cpp_follower", accept))

    assert ros_client.spin_until(lambda: both_at(OK), NODE_START_TIMEOUT_S), (python.failure(), cpp.failure())
    python_bus.stop(), cpp_bus.stop()
    assert ros_client.spin_until(lambda: both_at(ERROR), MESSAGE_TIMEOUT_S)
    for node, bus in ((python, python_bus), (cpp, cpp_bus)):
        code, stderr = node.wait()
        assert code == 3, stderr
        lines = stderr.strip().splitlines()
        assert any("[WARN]" in line and str(bus.link) in line for line in lines), stderr  # said at the first failure
        assert (
            lines[-1].split(": error: ", 1)[1] == f"{bus.link}: bus failing for 3 s: serial port {bus.link} not found"
        )
